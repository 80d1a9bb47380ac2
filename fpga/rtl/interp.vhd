-- Block "interp": the trilinear blend of the 8 corner voxels with the fractions
-- (voxel_frac UQ0.15), rounded once half to even to sample_value (UQ8.8):
-- value = round_he(sum_k wt_k v_k / 2^(45 - 8)), wt_k the product of the three axis
-- factors (1 - frac or frac) with 45 fraction bits (rtl_model/proc/sample_pipe.h
-- c5_interp_blend). The sum is exact (< 2^53), so the order of the additions is free.
--
-- Pipeline: INTERP_LATENCY = 2 (dp_pkg). Stage 1 registers the four x-y weight products;
-- stage 2 forms the eight weights, the dot product and the rounding into the output
-- register. One transaction a cycle; rst clears only the valid bits.
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

library work;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;

entity interp is
  port (
    clk, rst  : in  std_logic;
    in_valid  : in  std_logic;
    frac      : in  frac3_t;     -- x, y, z: weights of the upper corners
    v         : in  voxel8_t;    -- corner k = kx + 2 ky + 4 kz
    out_valid : out std_logic;
    value     : out std_logic_vector(SIG_SAMPLE_VALUE_WIDTH - 1 downto 0));
end entity interp;

architecture rtl of interp is
  signal s1_valid : std_logic := '0';
  signal s1_xy    : xy4_t;
  signal s1_fz    : frac_t;
  signal s1_v     : voxel8_t;
begin
  process (clk)
    variable wt  : wt8_t;
    variable acc : unsigned(WT_FRAC + VOXEL_BITS + 3 downto 0);  -- 8 terms: 3 bits more
    variable r   : unsigned(acc'length - (WT_FRAC - SIG_SAMPLE_VALUE_FRAC) downto 0);
  begin
    if rising_edge(clk) then
      -- stage 1
      s1_valid <= in_valid;
      s1_xy <= xy_products(frac);
      s1_fz <= frac(2);
      s1_v <= v;
      -- stage 2
      wt := tri_weights(s1_xy, s1_fz);
      acc := (others => '0');
      for k in 0 to 7 loop
        acc := acc + resize(wt(k) * unsigned(s1_v(k)), acc'length);
      end loop;
      r := rshift_he(acc, WT_FRAC - SIG_SAMPLE_VALUE_FRAC);
      value <= std_logic_vector(r(SIG_SAMPLE_VALUE_WIDTH - 1 downto 0));  -- <= 255.0: fits
      out_valid <= s1_valid;
      if rst = '1' then
        s1_valid <= '0';
        out_valid <= '0';
      end if;
    end if;
  end process;
end architecture rtl;
