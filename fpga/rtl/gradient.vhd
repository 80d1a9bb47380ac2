-- Block "gradient": per axis A the trilinear blend of the 8 corners' central differences
-- dA_k (v(c + e_A) - v(c - e_A), signed) with the interp weights, rounded half to even to
-- SQ8.8, then times the gradient scale gs_A (grad_scale UQ1.15) and rounded half to even
-- again to SQ8.8 (rtl_model/proc/sample_pipe.h c5_grad_blend):
--   grad_A = round_he(round_he(sum_k wt_k dA_k / 2^37) gs_A / 2^15).
-- Neither step saturates, as in the model: with gs <= 1 (min spacing / spacing) the
-- result is within +-255.0, inside SQ8.8; the output is the result's low 17 bits.
--
-- Pipeline: GRADIENT_LATENCY = 3 (dp_pkg). Stage 1: the four x-y weight products;
-- stage 2: the eight weights, three dot products and the first rounding; stage 3: the
-- scale and the second rounding into the output registers. One transaction a cycle; rst
-- clears only the valid bits.
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

library work;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;

entity gradient is
  port (
    clk, rst  : in  std_logic;
    in_valid  : in  std_logic;
    frac      : in  frac3_t;     -- x, y, z: weights of the upper corners
    d         : in  diff24_t;    -- d(A)(k): axis A, corner k = kx + 2 ky + 4 kz
    gs        : in  gscale3_t;
    out_valid : out std_logic;
    grad      : out grad3_t);
end entity gradient;

architecture rtl of gradient is
  constant SHIFT1   : positive := WT_FRAC - SIG_GRADIENT_FRAC;   -- 45 -> 8 fraction bits
  constant ACC_BITS : positive := WT_FRAC + 2 + DIFF_BITS + 3;   -- signed weight x diff, 8 terms
  constant B_BITS   : positive := ACC_BITS - SHIFT1 + 1;
  constant P_BITS   : positive := B_BITS + SIG_GRAD_SCALE_WIDTH + 1;
  type blend3_t is array (0 to 2) of signed(B_BITS - 1 downto 0);

  signal s1_valid : std_logic := '0';
  signal s1_xy    : xy4_t := (others => (others => '0'));
  signal s1_fz    : frac_t := (others => '0');
  signal s1_d     : diff24_t := (others => (others => (others => '0')));
  signal s1_gs, s2_gs : gscale3_t := (others => (others => '0'));
  signal s2_valid : std_logic := '0';
  signal s2_blend : blend3_t := (others => (others => '0'));
begin
  process (clk)
    variable wt  : wt8_t;
    variable acc : signed(ACC_BITS - 1 downto 0);
    variable p   : signed(P_BITS - 1 downto 0);
    variable r   : signed(P_BITS - SIG_GRAD_SCALE_FRAC downto 0);
  begin
    if rising_edge(clk) then
      -- stage 1
      s1_valid <= in_valid;
      s1_xy <= xy_products(frac);
      s1_fz <= frac(2);
      s1_d <= d;
      s1_gs <= gs;
      -- stage 2
      wt := tri_weights(s1_xy, s1_fz);
      for a in 0 to 2 loop
        acc := (others => '0');
        for k in 0 to 7 loop
          acc := acc + resize(signed('0' & wt(k)) * signed(s1_d(a)(k)), ACC_BITS);
        end loop;
        s2_blend(a) <= rshift_he(acc, SHIFT1);
      end loop;
      s2_gs <= s1_gs;
      s2_valid <= s1_valid;
      -- stage 3
      for a in 0 to 2 loop
        p := resize(s2_blend(a) * signed('0' & s2_gs(a)), P_BITS);
        r := rshift_he(p, SIG_GRAD_SCALE_FRAC);
        grad(a) <= std_logic_vector(r(SIG_GRADIENT_WIDTH - 1 downto 0));
      end loop;
      out_valid <= s2_valid;
      if rst = '1' then
        s1_valid <= '0';
        s2_valid <= '0';
        out_valid <= '0';
      end if;
    end if;
  end process;
end architecture rtl;
