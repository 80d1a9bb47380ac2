-- Block "composite": front-to-back compositing of one sample into the ray
-- (rtl_model/proc/sample_pipe.h c5_composite; docs/rendering-spec.md 5). With T = 1 - opa:
--   rgb'  = clamp(rgb + round_he(w T alpha c / 2^45), 0, 2^14 - 1) per channel, unless the
--           ray is a shadow ray (colour unchanged: shadow rays only attenuate);
--   opa'  = opa + round_he(T alpha / 2^15);  done = opa' >= a_max (early termination);
--   sat   = the number of clamped channels (the model's saturation count).
-- Formats: w UQ1.15 (the packet's contribution), opa and a_max UQ1.15 (max_opacity),
-- alpha UQ1.15 (tf_rgba), c UQ4.12 (shaded_rgb), rgb UQ2.12 (sample_rgb). The arithmetic
-- is signed and exact at every width, so an opacity above 1 (T < 0) gives the model's
-- bits too.
--
-- Pipeline: COMPOSITE_LATENCY = 3 (dp_pkg). Stage 1: T, w T and T alpha; stage 2:
-- w T alpha, opa' and done; stage 3: the colour products, rounding and clamps into the
-- output registers. One transaction a cycle; rst clears only the valid bits.
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

library work;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;

entity composite is
  port (
    clk, rst  : in  std_logic;
    in_valid  : in  std_logic;
    w         : in  std_logic_vector(RAY_PACKET_CONTRIBUTION_WIDTH - 1 downto 0);
    opa       : in  std_logic_vector(SIG_MAX_OPACITY_WIDTH - 1 downto 0);
    rgb       : in  rgb3_t;      -- r, g, b: the ray's colour
    alpha     : in  std_logic_vector(SIG_TF_RGBA_WIDTH - 1 downto 0);
    c         : in  shaded3_t;   -- r, g, b: the sample's shaded colour
    shadow    : in  std_logic;
    a_max     : in  std_logic_vector(SIG_MAX_OPACITY_WIDTH - 1 downto 0);
    out_valid : out std_logic;
    rgb_out   : out rgb3_t;
    opa_out   : out std_logic_vector(SIG_MAX_OPACITY_WIDTH - 1 downto 0);
    done      : out std_logic;
    sat       : out std_logic_vector(1 downto 0));  -- 0..3 clamped channels
end entity composite;

architecture rtl of composite is
  constant OF_BITS : positive := SIG_MAX_OPACITY_WIDTH;
  constant ONE     : integer := 2 ** SIG_MAX_OPACITY_FRAC;
  constant RGB_MAX : integer := 2 ** SIG_SAMPLE_RGB_WIDTH - 1;
  constant T_BITS  : positive := OF_BITS + 2;                       -- ONE - opa, signed
  constant WT_BITS : positive := T_BITS + RAY_PACKET_CONTRIBUTION_WIDTH + 1;
  constant TA_BITS : positive := T_BITS + SIG_TF_RGBA_WIDTH + 1;
  constant WTA_BITS : positive := WT_BITS + SIG_TF_RGBA_WIDTH + 1;
  constant P_BITS  : positive := WTA_BITS + SIG_SHADED_RGB_WIDTH + 1;
  -- w T alpha has 3 x 15 fraction bits, c 12, rgb 12: the product drops 45.
  constant P_SHIFT : positive := RAY_PACKET_CONTRIBUTION_WIDTH - 1 + SIG_MAX_OPACITY_FRAC
                                 + SIG_TF_RGBA_FRAC + SIG_SHADED_RGB_FRAC - SIG_SAMPLE_RGB_FRAC;

  function sgn(v : std_logic_vector) return signed is  -- unsigned value, one sign bit more
  begin
    return signed('0' & v);
  end function sgn;

  -- stage 1
  signal s1_valid, s1_shadow : std_logic := '0';
  signal s1_wt     : signed(WT_BITS - 1 downto 0) := (others => '0');
  signal s1_ta     : signed(TA_BITS - 1 downto 0) := (others => '0');
  signal s1_alpha  : std_logic_vector(alpha'range) := (others => '0');
  signal s1_opa, s1_amax : std_logic_vector(opa'range) := (others => '0');
  signal s1_rgb    : rgb3_t := (others => (others => '0'));
  signal s1_c      : shaded3_t := (others => (others => '0'));
  -- stage 2
  signal s2_valid, s2_shadow, s2_done : std_logic := '0';
  signal s2_wta    : signed(WTA_BITS - 1 downto 0) := (others => '0');
  signal s2_opa    : std_logic_vector(opa'range) := (others => '0');
  signal s2_rgb    : rgb3_t := (others => (others => '0'));
  signal s2_c      : shaded3_t := (others => (others => '0'));
begin
  process (clk)
    variable t    : signed(T_BITS - 1 downto 0);
    variable opa2 : signed(TA_BITS - SIG_MAX_OPACITY_FRAC + 1 downto 0);
    variable p    : signed(P_BITS - 1 downto 0);
    variable sum  : signed(P_BITS - P_SHIFT + 1 downto 0);
    variable n    : natural range 0 to 3;
  begin
    if rising_edge(clk) then
      -- stage 1
      t := to_signed(ONE, T_BITS) - resize(sgn(opa), T_BITS);
      s1_wt <= resize(sgn(w) * t, WT_BITS);
      s1_ta <= resize(t * sgn(alpha), TA_BITS);
      s1_valid <= in_valid;
      s1_shadow <= shadow;
      s1_alpha <= alpha;
      s1_opa <= opa;
      s1_amax <= a_max;
      s1_rgb <= rgb;
      s1_c <= c;
      -- stage 2
      s2_wta <= resize(s1_wt * sgn(s1_alpha), WTA_BITS);
      opa2 := resize(sgn(s1_opa), opa2'length) + resize(rshift_he(s1_ta, SIG_MAX_OPACITY_FRAC), opa2'length);
      s2_opa <= std_logic_vector(opa2(OF_BITS - 1 downto 0));
      s2_done <= '1' when opa2 >= resize(sgn(s1_amax), opa2'length) else '0';
      s2_valid <= s1_valid;
      s2_shadow <= s1_shadow;
      s2_rgb <= s1_rgb;
      s2_c <= s1_c;
      -- stage 3
      n := 0;
      for ch in 0 to 2 loop
        if s2_shadow = '1' then
          rgb_out(ch) <= s2_rgb(ch);
        else
          p := resize(s2_wta * sgn(s2_c(ch)), P_BITS);
          sum := resize(sgn(s2_rgb(ch)), sum'length) + resize(rshift_he(p, P_SHIFT), sum'length);
          rgb_out(ch) <= std_logic_vector(unsigned(clamp(sum, 0, RGB_MAX, SIG_SAMPLE_RGB_WIDTH + 1)(SIG_SAMPLE_RGB_WIDTH - 1 downto 0)));
          n := n + clamps(sum, 0, RGB_MAX);
        end if;
      end loop;
      sat <= std_logic_vector(to_unsigned(n, 2));
      opa_out <= s2_opa;
      done <= s2_done;
      out_valid <= s2_valid;
      if rst = '1' then
        s1_valid <= '0';
        s2_valid <= '0';
        out_valid <= '0';
      end if;
    end if;
  end process;
end architecture rtl;
