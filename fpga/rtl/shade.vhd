-- Block "shade": Phong shading of one sample (rtl_model/proc/sample_pipe.h c5_shade_w at the
-- shipped widths; docs/rendering-spec.md 4.3), bit for bit:
--   m2 = |g|^2 (16 fraction bits); m2 = 0: k = ka, ks = 0. Otherwise fade = min(2 m2, 2^15)
--   (UQ1.15: the lights' share, whole from |g| = 1/2, a quarter value step a voxel),
--   n = normalize(-g), turned to face the viewer (v = -dir) when n.v < 0; per light i
--   (n_lights of them) L = normalize(pos_i - gpos) (point) or dir_i (directional);
--   N.L = dot14(n, L); lights with N.L <= 0 are skipped; diff += I_i N.L;
--   H = normalize(L + v) (skipped when zero); N.H = dot14(n, H); when N.H > 0,
--   spec += I_i pow(N.H), pow linear between the 1,025 table entries at N.H >> 4
--   (entry 1024 for N.H >= 1);
--   k = clamp(ka + round_he(kd diff fade / 2^41)), ks = clamp(round_he(ks spec fade / 2^42)),
--   rgb_c = clamp(round_he(tf_c k / 2^15) + ks), every clamp to [0, 65535] counted in sat.
-- normalize(v): len = floor(sqrt(|v|^2 2^28)) (digit by digit), each component
-- round_he(v_a 2^28 / len) (restoring division, then the half-to-even step), 0 for v = 0.
-- Half to even is symmetric about 0, so a negative component is the negated rounding of
-- its magnitude, which is what c5_div_he64 gives.
--
-- A multi-cycle unit, not a pipeline: one square root and three divisions a
-- normalisation, up to 2 n_lights + 1 normalisations a sample, through one shared
-- iterative normaliser (1 root bit and 1 quotient bit per cycle). in_ready is 1 while it
-- is idle; a sample accepted in cycle 0 (in_valid and in_ready) gives out_valid (one
-- cycle) in cycle SHADE_FLAT_CYCLES = 3 when g = 0, else in cycle
--   SHADE_NORM_CYCLES + 6 + sum over the n_lights lights of
--     2, + SHADE_NORM_CYCLES for a point light, and when N.L > 0 + SHADE_NORM_CYCLES + 1,
--     then + 2 when H /= 0 and N.H >= 1, + 3 when H /= 0 and 0 < N.H < 1 (table reads),
-- SHADE_NORM_CYCLES = SHADE_ROOT_BITS + SHADE_Q_BITS + 3 = 65 (dp_pkg): the root's bits,
-- the quotient's bits and three steps. The testbench
-- measures every sample's latency and checks it against this formula.
--
-- Configuration: the registers (ka, kd, ks, n_lights, then 8 light slots of kind
-- (0 point, 1 directional), pos x y z, dir x y z, intensity; 32-bit two's complement, in
-- the order of the image shade.SOURCE.regs.hex) through reg_*, the power table
-- (shade.SOURCE.pow.hex) through pow_*; written while the unit is idle.
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

library work;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;

entity shade is
  port (
    clk, rst  : in  std_logic;
    reg_we    : in  std_logic;
    reg_addr  : in  std_logic_vector(6 downto 0);   -- 0 .. SHADE_REGS - 1
    reg_data  : in  std_logic_vector(31 downto 0);
    pow_we    : in  std_logic;
    pow_addr  : in  std_logic_vector(POW_ADDR_BITS - 1 downto 0);  -- 0 .. 2^10
    pow_data  : in  std_logic_vector(SIG_SPEC_POW_WIDTH - 1 downto 0);
    in_valid  : in  std_logic;
    in_ready  : out std_logic;
    grad      : in  grad3_t;                         -- SQ8.8
    tf        : in  tf3_t;                           -- r g b, UQ1.15
    gpos      : in  gpos3_t;                         -- SQ13.15 (geom coordinates)
    dir       : in  dir3_t;                          -- SQ1.14
    out_valid : out std_logic;
    rgb       : out shaded3_t;                       -- UQ4.12
    sat       : out std_logic_vector(2 downto 0));   -- clamps: 0 .. 5
end entity shade;

architecture rtl of shade is
  constant V_BITS  : positive := SHADE_V_BITS;       -- a vector to normalise (|v_a| < 2^30)
  constant D2_BITS : positive := 2 * V_BITS;         -- |v|^2 < 3 2^60
  constant X_BITS  : positive := D2_BITS + 28;       -- |v|^2 2^28, even
  constant R_BITS  : positive := SHADE_ROOT_BITS;    -- the root: X_BITS / 2
  constant P_BITS  : positive := R_BITS + 2;         -- a partial remainder (< 2 root)
  constant Q_BITS  : positive := SHADE_Q_BITS;       -- |quotient| <= 2^14 + 1
  constant NRM_BITS : positive := SIG_NORMAL_WIDTH + 2;  -- a unit vector's component, 2^14 + 1
  constant ACC_BITS : positive := 64;                -- diff and spec, int64 in the model
  constant LT_MAX  : integer := 2 ** SIG_LIGHT_TERM_WIDTH - 1;
  constant RGB_MAX : integer := 2 ** SIG_SHADED_RGB_WIDTH - 1;
  constant ONE14   : integer := 2 ** SIG_NORMAL_FRAC;

  type v3_t   is array (0 to 2) of signed(V_BITS - 1 downto 0);
  type nrm3_t is array (0 to 2) of signed(NRM_BITS - 1 downto 0);
  type q3_t   is array (0 to 2) of unsigned(Q_BITS - 1 downto 0);
  type n3_t   is array (0 to 2) of unsigned(P_BITS - 1 downto 0);
  type regs_t is array (0 to SHADE_REGS - 1) of signed(31 downto 0);
  type pow_t  is array (0 to 2 ** POW_TABLE_BITS) of std_logic_vector(SIG_SPEC_POW_WIDTH - 1 downto 0);

  signal regs : regs_t;
  signal pow  : pow_t;
  signal pow_rd : std_logic_vector(SIG_SPEC_POW_WIDTH - 1 downto 0);
  signal pow_ra : natural range 0 to 2 ** POW_TABLE_BITS := 0;

  type state_t is (IDLE, GRAD_MAG, NORM_ROOT, NORM_DIV, NORM_ROUND, FACE, LIGHT, LDOT, HDOT,
                   POW_A, POW_B, POW_W, POW_C, KTERMS, OUTPUT);
  signal st : state_t := IDLE;
  signal ret : state_t := IDLE;                      -- where a normalisation returns
  -- the sample
  signal g_r   : grad3_t;
  signal tf_r  : tf3_t;
  signal gp_r  : gpos3_t;
  signal v_r   : v3_t;                               -- -dir, the view vector
  -- the normaliser
  signal nv    : v3_t;                               -- the vector
  signal x_r   : unsigned(X_BITS - 1 downto 0);
  signal rem_r : unsigned(R_BITS + 1 downto 0);
  signal root  : unsigned(R_BITS - 1 downto 0);
  signal num   : n3_t;                               -- the partial remainders
  signal quo   : q3_t;
  signal step  : natural range 0 to R_BITS;
  signal nres  : nrm3_t;                             -- the unit vector
  signal nzero : boolean;                            -- v was 0
  -- the lighting
  signal n_r   : nrm3_t;                             -- the normal
  signal ldir  : v3_t;                               -- L as used: point or directional
  signal li    : natural range 0 to 8;
  signal diff, spec : signed(ACC_BITS - 1 downto 0);
  signal ndh_r : signed(NRM_BITS + 1 downto 0);
  signal p0    : signed(SIG_SPEC_POW_WIDTH downto 0);
  signal k_r, ks_r : signed(SIG_LIGHT_TERM_WIDTH + 1 downto 0);
  signal fade_r : signed(16 downto 0);               -- UQ1.15, 0 < fade <= 1
  signal nsat  : natural range 0 to 7;

  function reg_base(i : natural) return natural is  -- light slot i's first register
  begin
    return 4 + 8 * i;
  end function reg_base;

  -- round_he(sum a_i b_i / 2^14): the model's c5_geom_dot14
  function dot14(a : nrm3_t; b : v3_t) return signed is
    variable s : signed(NRM_BITS + V_BITS + 1 downto 0) := (others => '0');
  begin
    for i in 0 to 2 loop
      s := s + resize(a(i) * b(i), s'length);
    end loop;
    return rshift_he(s, SIG_NORMAL_FRAC);
  end function dot14;

  function to_v3(n : nrm3_t) return v3_t is
    variable v : v3_t;
  begin
    for i in 0 to 2 loop
      v(i) := resize(n(i), V_BITS);
    end loop;
    return v;
  end function to_v3;
begin
  in_ready <= '1' when st = IDLE else '0';

  -- the registers (flip-flops: read at several addresses at once), one compare a
  -- register: ghdl 2.0 --synth wrote an indexed write (regs(addr) <= ...) as a
  -- combinational loop instead of flip-flops.
  config_regs : process (clk)
  begin
    if rising_edge(clk) then
      for i in regs'range loop  -- (reg_addr is wider than the 68 registers need)
        if reg_we = '1' and unsigned(reg_addr) = i then
          regs(i) <= signed(reg_data);
        end if;
      end loop;
    end if;
  end process config_regs;

  -- the power table (block RAM: registered read)
  config_pow : process (clk)
  begin
    if rising_edge(clk) then
      if pow_we = '1' then
        pow(to_integer(unsigned(pow_addr))) <= pow_data;
      end if;
      pow_rd <= pow(pow_ra);
    end if;
  end process config_pow;

  fsm : process (clk)
    variable m2   : signed(2 * SIG_GRADIENT_WIDTH + 1 downto 0);
    variable d2   : unsigned(D2_BITS - 1 downto 0);
    variable trial : unsigned(R_BITS + 1 downto 0);
    variable rem_v : unsigned(R_BITS + 1 downto 0);
    variable q    : unsigned(Q_BITS downto 0);
    variable pr   : unsigned(P_BITS - 1 downto 0);
    variable d    : signed(NRM_BITS + V_BITS - SIG_NORMAL_FRAC + 2 downto 0);
    variable t    : v3_t;
    variable lin  : signed(SIG_SPEC_POW_WIDTH + 6 downto 0);
    variable prod : signed(ACC_BITS + 32 downto 0);
    variable prodf : signed(ACC_BITS + 32 + 17 downto 0);
    variable kk   : signed(ACC_BITS + 32 - 25 downto 0);
    variable c    : signed(SIG_TF_RGBA_WIDTH + SIG_LIGHT_TERM_WIDTH + 3 downto 0);
    variable cs   : signed(c'length - SIG_TF_RGBA_FRAC + 1 downto 0);
    variable n    : natural range 0 to 7;
    variable kind : signed(31 downto 0);

    -- start a normalisation of vec, returning to state back
    procedure normalize(vec : v3_t; back : state_t) is
      variable s : unsigned(D2_BITS - 1 downto 0) := (others => '0');
    begin
      for i in 0 to 2 loop
        s := s + unsigned(resize(vec(i) * vec(i), D2_BITS));
      end loop;
      nv <= vec;
      x_r <= shift_left(resize(s, X_BITS), 28);
      rem_r <= (others => '0');
      root <= (others => '0');
      step <= R_BITS;
      ret <= back;
      st <= NORM_ROOT;
    end procedure normalize;

    -- the next light, or the light terms after the last
    procedure next_light(i : natural) is
    begin
      li <= i;
      st <= LIGHT;
    end procedure next_light;
  begin
    if rising_edge(clk) then
      out_valid <= '0';
      case st is
        when IDLE =>
          if in_valid = '1' then
            g_r <= grad;
            tf_r <= tf;
            gp_r <= gpos;
            for a in 0 to 2 loop
              v_r(a) <= -resize(signed(dir(a)), V_BITS);
            end loop;
            st <= GRAD_MAG;
          end if;

        when GRAD_MAG =>
          m2 := (others => '0');
          for a in 0 to 2 loop
            m2 := m2 + resize(signed(g_r(a)) * signed(g_r(a)), m2'length);
          end loop;
          diff <= (others => '0');
          spec <= (others => '0');
          nsat <= 0;
          if m2 = 0 then  -- no gradient: ambient alone
            k_r <= resize(regs(0), k_r'length);
            ks_r <= (others => '0');
            st <= OUTPUT;
          else
            if m2 < 16384 then  -- |g| < 1/2: the lights' share fades, 4 |g|^2
              fade_r <= resize(shift_left(m2, 1), 17);
            else
              fade_r <= to_signed(2 ** 15, 17);
            end if;
            for a in 0 to 2 loop
              t(a) := -resize(signed(g_r(a)), V_BITS);
            end loop;
            normalize(t, FACE);
          end if;

        -- digit-by-digit square root, two bits of x a cycle
        when NORM_ROOT =>
          if step = 0 then
            -- the partial remainders start at |v_a| 2^28 / 2^Q_BITS (below the root, as
            -- |v_a| <= |v|): Q_BITS quotient bits remain, the dividend's low bits are 0
            for a in 0 to 2 loop
              num(a) <= shift_left(resize(magnitude(nv(a)), P_BITS), 28 - Q_BITS);
              quo(a) <= (others => '0');
            end loop;
            step <= Q_BITS;
            st <= NORM_DIV;
          else
            rem_v := shift_left(rem_r, 2) + resize(x_r(X_BITS - 1 downto X_BITS - 2), rem_v'length);
            x_r <= shift_left(x_r, 2);
            trial := shift_left(resize(root, trial'length), 2) + 1;
            if rem_v >= trial then
              rem_r <= rem_v - trial;
              root <= shift_left(root, 1) + 1;
            else
              rem_r <= rem_v;
              root <= shift_left(root, 1);
            end if;
            step <= step - 1;
          end if;

        -- restoring division of the three magnitudes by the root, one quotient bit a cycle
        when NORM_DIV =>
          if step = 0 then
            st <= NORM_ROUND;
          else
            for a in 0 to 2 loop
              pr := shift_left(num(a), 1);
              if pr >= resize(root, P_BITS) then
                num(a) <= pr - resize(root, P_BITS);
                quo(a) <= shift_left(quo(a), 1) + 1;
              else
                num(a) <= pr;
                quo(a) <= shift_left(quo(a), 1);
              end if;
            end loop;
            step <= step - 1;
          end if;

        -- half to even on the remainder, then the sign
        -- (v = 0, root 0: the result is 0 and flagged)
        when NORM_ROUND =>
          nzero <= root = 0;
          for a in 0 to 2 loop
            q := resize(quo(a), Q_BITS + 1);
            pr := shift_left(num(a), 1);
            if pr > resize(root, P_BITS) or (pr = resize(root, P_BITS) and q(0) = '1') then
              q := q + 1;
            end if;
            if root = 0 then
              nres(a) <= (others => '0');
            elsif nv(a) < 0 then
              nres(a) <= -resize(signed(q), NRM_BITS);
            else
              nres(a) <= resize(signed(q), NRM_BITS);
            end if;
          end loop;
          st <= ret;

        -- the normal faces the viewer
        when FACE =>
          if dot14(nres, v_r) < 0 then
            for a in 0 to 2 loop
              n_r(a) <= -nres(a);
            end loop;
          else
            n_r <= nres;
          end if;
          next_light(0);

        when LIGHT =>
          if li = to_integer(regs(3)) or li = 8 then
            st <= KTERMS;
          else
            kind := regs(reg_base(li));
            if kind = 0 then  -- point: L = normalize(pos - gpos)
              for a in 0 to 2 loop
                t(a) := resize(regs(reg_base(li) + 1 + a), V_BITS) - resize(signed(gp_r(a)), V_BITS);
              end loop;
              normalize(t, LDOT);
            else
              for a in 0 to 2 loop
                ldir(a) <= resize(regs(reg_base(li) + 4 + a), V_BITS);
              end loop;
              st <= LDOT;
            end if;
          end if;

        -- N.L; then H = normalize(L + v)
        when LDOT =>
          if regs(reg_base(li)) = 0 then
            t := to_v3(nres);  -- the point light's L, just normalised
          else
            t := ldir;
          end if;
          d := resize(dot14(n_r, t), d'length);
          if d <= 0 then
            next_light(li + 1);
          else
            diff <= diff + resize(resize(regs(reg_base(li) + 7), 33) * d, ACC_BITS);
            for a in 0 to 2 loop
              t(a) := t(a) + v_r(a);
            end loop;
            normalize(t, HDOT);
          end if;

        -- N.H and the table reads
        when HDOT =>
          if nzero then
            next_light(li + 1);
          else
            d := resize(dot14(n_r, to_v3(nres)), d'length);
            ndh_r <= resize(d, ndh_r'length);
            if d <= 0 then
              next_light(li + 1);
            elsif d >= ONE14 then
              pow_ra <= 2 ** POW_TABLE_BITS;
              st <= POW_W;
            else
              pow_ra <= to_integer(shift_right(d, 4));
              st <= POW_A;
            end if;
          end if;

        when POW_A =>  -- entry i being read; address i + 1 next
          pow_ra <= pow_ra + 1;
          st <= POW_B;
        when POW_W =>  -- entry 1024 being read
          st <= POW_C;
        when POW_B =>  -- entry i read; entry i + 1 being read
          p0 <= signed('0' & pow_rd);
          st <= POW_C;
        when POW_C =>
          if ndh_r >= ONE14 then  -- pow_rd is entry 1024
            lin := resize(signed('0' & pow_rd), lin'length);
          else  -- round_he((p0 16 + (p1 - p0) f) / 16)
            lin := resize(rshift_he(shift_left(resize(p0, lin'length), 4)
                     + resize((signed('0' & pow_rd) - p0) * signed('0' & std_logic_vector(ndh_r(3 downto 0))), lin'length), 4), lin'length);
          end if;
          spec <= spec + resize(resize(regs(reg_base(li) + 7), 33) * lin, ACC_BITS);
          next_light(li + 1);

        when KTERMS =>
          n := 0;
          prod := resize(resize(regs(1), 33) * diff, prod'length);  -- kd diff
          prodf := resize(prod * fade_r, prodf'length);
          kk := resize(resize(regs(0), kk'length) + resize(rshift_he(prodf, 26 + 15), kk'length), kk'length);
          k_r <= resize(clamp(kk, 0, LT_MAX, SIG_LIGHT_TERM_WIDTH + 1), k_r'length);
          n := n + clamps(kk, 0, LT_MAX);
          prod := resize(resize(regs(2), 33) * spec, prod'length);  -- ks spec
          prodf := resize(prod * fade_r, prodf'length);
          kk := resize(rshift_he(prodf, 27 + 15), kk'length);
          ks_r <= resize(clamp(kk, 0, LT_MAX, SIG_LIGHT_TERM_WIDTH + 1), ks_r'length);
          n := n + clamps(kk, 0, LT_MAX);
          nsat <= n;
          st <= OUTPUT;

        when OUTPUT =>
          n := nsat;
          for ch in 0 to 2 loop
            c := resize(signed('0' & tf_r(ch)) * k_r, c'length);
            cs := rshift_he(c, SIG_TF_RGBA_FRAC) + resize(ks_r, cs'length);
            rgb(ch) <= std_logic_vector(clamp(cs, 0, RGB_MAX, SIG_SHADED_RGB_WIDTH + 1)(SIG_SHADED_RGB_WIDTH - 1 downto 0));
            n := n + clamps(cs, 0, RGB_MAX);
          end loop;
          sat <= std_logic_vector(to_unsigned(n, 3));
          out_valid <= '1';
          st <= IDLE;
      end case;
      if rst = '1' then
        st <= IDLE;
        out_valid <= '0';
      end if;
    end if;
  end process fsm;
end architecture rtl;
