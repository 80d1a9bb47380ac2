-- Block "classify": the transfer-function lookup of one sample (rtl_model/proc/sample_pipe.h
-- c5_classify). value (sample_value UQ8.8) = i + f / 2^8; out: tf_rgba (4 x UQ1.15)
--   rgba = round_he((tf[i] 2^8 + (tf[i + 1] - tf[i]) f) / 2^8),
-- linear between entries i and i + 1, one rounding half to even; for value >= 255.0 the
-- top clamp i = 254, f = 2^8 (entry 255 exactly).
--
-- The table (2^8 entries of r g b a, UQ1.15 each, alpha step-corrected) is written
-- through the tf_* port (the DSP loads it per frame; the testbench from the image
-- CLASSIFY.SOURCE.tf.hex). A lookup reads two neighbouring entries in one cycle, so the
-- table is held twice (two simple dual-port RAMs written alike: block RAM on an FPGA),
-- one read at i, the other at i + 1.
--
-- Pipeline: CLASSIFY_LATENCY = 2 (dp_pkg). Stage 1: the index and fraction, the two
-- synchronous RAM reads; stage 2: the blend and rounding into the output registers. One
-- lookup a cycle; a table write takes effect for lookups entering after it.
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

library work;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;

entity classify is
  port (
    clk, rst  : in  std_logic;
    tf_we     : in  std_logic;                 -- table write
    tf_addr   : in  std_logic_vector(VOXEL_BITS - 1 downto 0);
    tf_data   : in  rgba4_t;
    in_valid  : in  std_logic;
    value     : in  std_logic_vector(SIG_SAMPLE_VALUE_WIDTH - 1 downto 0);
    out_valid : out std_logic;
    rgba      : out rgba4_t);
end entity classify;

architecture rtl of classify is
  constant F_BITS  : positive := SIG_SAMPLE_VALUE_FRAC;
  constant ENTRIES : positive := 2 ** VOXEL_BITS;
  constant E_BITS  : positive := SIG_TF_RGBA_WIDTH;
  subtype entry_t is std_logic_vector(4 * E_BITS - 1 downto 0);
  type ram_t is array (0 to ENTRIES - 1) of entry_t;

  function pack(d : rgba4_t) return entry_t is
  begin
    return d(0) & d(1) & d(2) & d(3);
  end function pack;
  function ch(e : entry_t; k : natural) return signed is  -- channel k, one sign bit more
  begin
    return signed('0' & e((4 - k) * E_BITS - 1 downto (3 - k) * E_BITS));
  end function ch;

  signal ram_lo, ram_hi : ram_t;  -- entry i and entry i + 1 of a lookup
  signal s1_valid : std_logic := '0';
  signal s1_lo, s1_hi : entry_t := (others => '0');
  signal s1_f : unsigned(F_BITS downto 0) := (others => '0');  -- 0 .. 2^8
begin
  process (clk)
    variable i : natural range 0 to ENTRIES - 1;
    variable f : unsigned(F_BITS downto 0);
    variable acc : signed(E_BITS + F_BITS + 2 downto 0);
    variable r : signed(E_BITS + 3 downto 0);
  begin
    if rising_edge(clk) then
      if tf_we = '1' then
        ram_lo(to_integer(unsigned(tf_addr))) <= pack(tf_data);
        ram_hi(to_integer(unsigned(tf_addr))) <= pack(tf_data);
      end if;
      -- stage 1
      i := to_integer(unsigned(value(value'high downto F_BITS)));
      f := resize(unsigned(value(F_BITS - 1 downto 0)), F_BITS + 1);
      if i > ENTRIES - 2 then
        i := ENTRIES - 2;
        f := to_unsigned(2 ** F_BITS, F_BITS + 1);
      end if;
      s1_lo <= ram_lo(i);
      s1_hi <= ram_hi(i + 1);
      s1_f <= f;
      s1_valid <= in_valid;
      -- stage 2
      for k in 0 to 3 loop
        acc := shift_left(resize(ch(s1_lo, k), acc'length), F_BITS)
               + resize((ch(s1_hi, k) - ch(s1_lo, k)) * signed('0' & s1_f), acc'length);
        r := rshift_he(acc, F_BITS);
        rgba(k) <= std_logic_vector(r(E_BITS - 1 downto 0));  -- between two entries: fits
      end loop;
      out_valid <= s1_valid;
      if rst = '1' then
        s1_valid <= '0';
        out_valid <= '0';
      end if;
    end if;
  end process;
end architecture rtl;
