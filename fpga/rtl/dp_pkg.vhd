-- The per-sample datapath's shared arithmetic and pipeline latencies (fpga/rtl/interp.vhd,
-- gradient.vhd, classify.vhd, composite.vhd).
--
-- The rounding and saturation are the C model's (rtl_model/proc/fxops.h): the exact result
-- first, then one rounding half to even (c5_rshift_he: floor(x / 2^s), +1 when the dropped
-- bits exceed one half, or equal it and the kept LSB is odd), then, where the model
-- clamps, saturation (c5_clamp64). Every width comes from the generated package
-- (build/gen/c5_layouts_pkg.vhd, spec/layouts.toml); the few derived here say from what.
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

library work;
use work.c5_layouts_pkg.all;

package dp_pkg is
  -- Pipeline latency of each block: the inputs driven in clock cycle k (with in_valid)
  -- give out_valid and the outputs in cycle k + LATENCY (one register stage a cycle, the
  -- last one the output register). A new transaction may enter every cycle.
  constant INTERP_LATENCY    : positive := 2;
  constant GRADIENT_LATENCY  : positive := 3;
  constant CLASSIFY_LATENCY  : positive := 2;
  constant COMPOSITE_LATENCY : positive := 3;
  -- shade is a multi-cycle unit (fpga/rtl/shade.vhd has its latency formula): its
  -- normaliser's operand width (the 32-bit light registers), root and quotient widths.
  constant SHADE_V_BITS      : positive := 32;
  constant SHADE_ROOT_BITS   : positive := (2 * SHADE_V_BITS + 28) / 2;  -- sqrt(|v|^2 2^28)
  constant SHADE_Q_BITS      : positive := SIG_NORMAL_FRAC + 2;          -- |v_a 2^28 / len| <= 2^14 + 1
  constant SHADE_NORM_CYCLES : positive := SHADE_ROOT_BITS + SHADE_Q_BITS + 3;
  constant SHADE_FLAT_CYCLES : positive := 3;
  constant SHADE_REGS        : positive := 4 + 8 * 8;  -- ka kd ks n_lights, 8 light slots of 8
  constant POW_TABLE_BITS    : positive := 10;         -- 2^10 + 1 entries over N.H in [0, 1]
  constant POW_ADDR_BITS     : positive := POW_TABLE_BITS + 1;
  constant TRAVERSE_LATENCY  : positive := 3;

  -- traverse: positions in the grid's voxel coordinates (signal grid_pos, SQ13.15: the step
  -- vector's fraction, signed, 13 integer bits for the model's 8,000-voxel grids) and voxel
  -- indices and counts (grid_coord, 13 bits), declared in spec/layouts.toml.
  constant POS_FRAC    : positive := SIG_GRID_POS_FRAC;
  constant GRID_BITS   : positive := SIG_GRID_COORD_WIDTH;
  constant POS_BITS    : positive := SIG_GRID_POS_WIDTH;
  constant BLOCK_BITS  : positive := 3;                           -- 8^3 space-leaping blocks
  constant LEAPED_BITS : positive := BLOCK_BITS + POS_FRAC + 1;   -- up to 8 voxels / 2^-15
  constant LIFE_NONE   : natural := 2 ** RAY_PACKET_LIFETIME_WIDTH - 1;  -- unbounded

  -- A voxel is the integer part of sample_value (UQ8.8: 8-bit voxels); a central
  -- difference of two voxels needs one bit more, signed.
  constant VOXEL_BITS : positive := SIG_SAMPLE_VALUE_WIDTH - SIG_SAMPLE_VALUE_FRAC;
  constant DIFF_BITS  : positive := VOXEL_BITS + 1;
  -- The trilinear weights: a product of three voxel_frac-based factors in [0, 1].
  constant FRAC_BITS  : positive := SIG_VOXEL_FRAC_FRAC;
  constant WT_FRAC    : positive := 3 * FRAC_BITS;

  subtype frac_t  is std_logic_vector(SIG_VOXEL_FRAC_WIDTH - 1 downto 0);
  subtype voxel_t is std_logic_vector(VOXEL_BITS - 1 downto 0);
  subtype diff_t  is std_logic_vector(DIFF_BITS - 1 downto 0);
  type frac3_t   is array (0 to 2) of frac_t;
  type voxel8_t  is array (0 to 7) of voxel_t;   -- corner k = kx + 2 ky + 4 kz
  type diff8_t   is array (0 to 7) of diff_t;
  type diff24_t  is array (0 to 2) of diff8_t;   -- per axis x, y, z
  -- Colours: the ray's (sample_rgb UQ2.12, the packet's red/green/blue) and a shaded
  -- sample's (shaded_rgb UQ4.12), r, g, b.
  type rgb3_t    is array (0 to 2) of std_logic_vector(SIG_SAMPLE_RGB_WIDTH - 1 downto 0);
  type shaded3_t is array (0 to 2) of std_logic_vector(SIG_SHADED_RGB_WIDTH - 1 downto 0);
  -- A transfer-function entry or a classified sample: r, g, b, a (tf_rgba UQ1.15).
  type rgba4_t   is array (0 to 3) of std_logic_vector(SIG_TF_RGBA_WIDTH - 1 downto 0);
  -- Per axis x, y, z: the gradient scale (grad_scale UQ1.15) and the gradient (SQ8.8).
  type gscale3_t is array (0 to 2) of std_logic_vector(SIG_GRAD_SCALE_WIDTH - 1 downto 0);
  type grad3_t   is array (0 to 2) of std_logic_vector(SIG_GRADIENT_WIDTH - 1 downto 0);
  -- shade's inputs: the table colour r g b (tf_rgba UQ1.15), the sample in geom
  -- coordinates (geom_coord SQ13.15), the ray's direction (the packet's, SQ1.14).
  type tf3_t   is array (0 to 2) of std_logic_vector(SIG_TF_RGBA_WIDTH - 1 downto 0);
  type gpos3_t is array (0 to 2) of std_logic_vector(SIG_GEOM_COORD_WIDTH - 1 downto 0);
  type dir3_t  is array (0 to 2) of std_logic_vector(RAY_PACKET_DIR_X_WIDTH - 1 downto 0);
  -- traverse's per-axis vectors
  type pos3_t  is array (0 to 2) of std_logic_vector(POS_BITS - 1 downto 0);
  type step3_t is array (0 to 2) of std_logic_vector(SIG_STEP_VEC_WIDTH - 1 downto 0);
  type grid3_t is array (0 to 2) of std_logic_vector(GRID_BITS - 1 downto 0);
  -- The 8 trilinear weights (WT_FRAC fraction bits, 1.0 included: one bit more).
  type wt8_t is array (0 to 7) of unsigned(WT_FRAC downto 0);

  -- floor(x / 2^s) rounded half to even (c5_rshift_he), x'length - s + 1 bits (the one
  -- extra bit holds the carry of rounding the largest value up). s >= 1.
  function rshift_he(x : signed; s : positive) return signed;
  -- The same for unsigned x (a zero sign bit added; the result has no sign bit).
  function rshift_he(x : unsigned; s : positive) return unsigned;
  -- |x|, one bit wider (written out: ghdl --synth's Verilog output has no abs).
  function magnitude(x : signed) return unsigned;
  -- x clamped to [lo, hi], returned in `width` bits (signed: lo may be negative).
  function clamp(x : signed; lo, hi : integer; width : positive) return signed;
  -- 1 when x lies outside [lo, hi] (c5_clamp64 counts one saturation).
  function clamps(x : signed; lo, hi : integer) return natural;

  -- The trilinear weights of the fractions in the order of c5_tri_weights: the four x-y
  -- products, then times the z factor. Split in two steps because the pipelines register
  -- the x-y products in between.
  type xy4_t is array (0 to 3) of unsigned(2 * FRAC_BITS downto 0);
  function xy_products(fr : frac3_t) return xy4_t;
  function z_factor(fz : frac_t; kz : natural) return unsigned;
  function tri_weights(xy : xy4_t; fz : frac_t) return wt8_t;
end package dp_pkg;

package body dp_pkg is
  function rshift_he(x : signed; s : positive) return signed is
    constant N : positive := x'length;
    variable xv : signed(N - 1 downto 0) := x;
    variable q : signed(N - s downto 0);
    variable below : boolean := false;  -- a dropped bit under the half bit is 1
  begin
    q := resize(xv(N - 1 downto s), N - s + 1);  -- floor (arithmetic shift)
    for i in 0 to s - 2 loop
      if xv(i) = '1' then
        below := true;
      end if;
    end loop;
    if xv(s - 1) = '1' and (below or q(0) = '1') then
      q := q + 1;
    end if;
    return q;
  end function rshift_he;

  function rshift_he(x : unsigned; s : positive) return unsigned is
    variable xs : signed(x'length downto 0);  -- x with a zero sign bit
    variable r : signed(x'length - s + 1 downto 0);
  begin
    xs := signed(resize(x, x'length + 1));
    r := rshift_he(xs, s);
    return unsigned(r(x'length - s downto 0));
  end function rshift_he;

  function magnitude(x : signed) return unsigned is
    variable w : signed(x'length downto 0) := resize(x, x'length + 1);
  begin
    if w < 0 then
      w := -w;
    end if;
    return unsigned(w);
  end function magnitude;

  function clamp(x : signed; lo, hi : integer; width : positive) return signed is
  begin
    if x < lo then
      return to_signed(lo, width);
    elsif x > hi then
      return to_signed(hi, width);
    end if;
    return resize(x, width);
  end function clamp;

  function clamps(x : signed; lo, hi : integer) return natural is
  begin
    if x < lo or x > hi then
      return 1;
    end if;
    return 0;
  end function clamps;

  -- factor 0 of an axis: 1 - frac; factor 1: frac (FRAC_BITS + 1 bits: 1.0 fits).
  function factor(f : frac_t; k : natural) return unsigned is
    constant ONE : unsigned(FRAC_BITS downto 0) := to_unsigned(2 ** FRAC_BITS, FRAC_BITS + 1);
  begin
    if k = 0 then
      return ONE - resize(unsigned(f), FRAC_BITS + 1);
    end if;
    return resize(unsigned(f), FRAC_BITS + 1);
  end function factor;

  function xy_products(fr : frac3_t) return xy4_t is
    variable xy : xy4_t;
  begin
    for ky in 0 to 1 loop
      for kx in 0 to 1 loop
        xy(kx + 2 * ky) := resize(factor(fr(0), kx) * factor(fr(1), ky), 2 * FRAC_BITS + 1);
      end loop;
    end loop;
    return xy;
  end function xy_products;

  function z_factor(fz : frac_t; kz : natural) return unsigned is
  begin
    return factor(fz, kz);
  end function z_factor;

  function tri_weights(xy : xy4_t; fz : frac_t) return wt8_t is
    variable wt : wt8_t;
  begin
    for kz in 0 to 1 loop
      for j in 0 to 3 loop
        wt(j + 4 * kz) := resize(xy(j) * z_factor(fz, kz), WT_FRAC + 1);
      end loop;
    end loop;
    return wt;
  end function tri_weights;
end package body dp_pkg;
