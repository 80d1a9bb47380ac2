-- Classification against the C model running beside it (docs/vectors.md, "The model inside
-- the simulator"): a transfer-function table drawn from SEED (entries 0, 1.0 or random) is
-- written into fpga/rtl/classify.vhd's table and the model's (c5ref_cl_table), then one
-- sample value a cycle (random, on an entry, half-way between two, or above 255.0 where the
-- lookup clamps) goes into both; the model's r g b a are held for CLASSIFY_LATENCY cycles
-- and compared with the DUT's then. The first difference ends the run:
-- "FAIL tb_classify_live: seed S sample N: rgba(C): model X, VHDL Y".
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use ieee.math_real.all;
use std.env.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.c5ref_pkg.all;

entity tb_classify_live is
  generic (SEED : positive := 1; SAMPLES : positive := 5000);
end entity tb_classify_live;

architecture sim of tb_classify_live is
  constant HALF : time := 5 ns;
  constant LAT : positive := CLASSIFY_LATENCY;
  signal clk, rst, in_valid, out_valid, tf_we : std_logic := '0';
  signal tf_addr : std_logic_vector(VOXEL_BITS - 1 downto 0) := (others => '0');
  signal tf_data, rgba : rgba4_t := (others => (others => '0'));
  signal value : std_logic_vector(SIG_SAMPLE_VALUE_WIDTH - 1 downto 0) := (others => '0');
begin
  dut : entity work.classify
    port map (clk => clk, rst => rst, tf_we => tf_we, tf_addr => tf_addr, tf_data => tf_data,
              in_valid => in_valid, value => value, out_valid => out_valid, rgba => rgba);

  run : process
    variable s1 : positive := SEED;
    variable s2 : positive := 20261127;
    variable r : real;
    variable x, rc : integer;
    type c4_t is array (0 to 3) of integer;
    type ring_t is array (0 to LAT) of c4_t;
    variable ring : ring_t;
    variable e : c4_t;
    constant ONE : integer := 2 ** SIG_TF_RGBA_FRAC;
    constant VMAX : integer := 2 ** SIG_SAMPLE_VALUE_WIDTH - 1;

    impure function pick(n : positive) return natural is
    begin
      uniform(s1, s2, r);
      return integer(floor(r * real(n))) mod n;
    end function;

    procedure tick is
    begin
      wait for HALF;
      clk <= '1';
      wait for HALF;
      clk <= '0';
    end procedure;
  begin
    rst <= '1';
    tick;
    rst <= '0';
    for i in 0 to 255 loop  -- the table, one entry a cycle
      for ch in 0 to 3 loop
        case pick(4) is
          when 0 => x := 0;
          when 1 => x := ONE;
          when others => x := pick(ONE + 1);
        end case;
        tf_data(ch) <= std_logic_vector(to_unsigned(x, SIG_TF_RGBA_WIDTH));
        rc := c5ref_cl_table(i, ch, x);
      end loop;
      tf_we <= '1';
      tf_addr <= std_logic_vector(to_unsigned(i, VOXEL_BITS));
      tick;
    end loop;
    tf_we <= '0';
    for n in 0 to SAMPLES + LAT - 1 loop
      if n < SAMPLES then
        case pick(5) is
          when 0 => x := 256 * pick(256);               -- on an entry
          when 1 => x := 256 * pick(256) + 128;         -- half-way: the rounding tie
          when 2 => x := 65280 + pick(VMAX - 65280 + 1); -- 255.0 and above: clamped
          when others => x := pick(VMAX + 1);
        end case;
        value <= std_logic_vector(to_unsigned(x, SIG_SAMPLE_VALUE_WIDTH));
        for ch in 0 to 3 loop
          e(ch) := c5ref_cl_run(x, ch);
        end loop;
        ring(n mod (LAT + 1)) := e;
        in_valid <= '1';
      else
        in_valid <= '0';
      end if;
      wait for HALF;  -- clock low: this cycle's outputs are stable
      if n >= LAT then
        e := ring((n - LAT) mod (LAT + 1));
        live_expect("tb_classify_live", SEED, "sample", n - LAT, "out_valid", 1, live_bit(out_valid));
        for ch in 0 to 3 loop
          live_expect("tb_classify_live", SEED, "sample", n - LAT, "rgba(" & integer'image(ch) & ")", e(ch),
                      to_integer(unsigned(rgba(ch))));
        end loop;
      end if;
      clk <= '1';
      wait for HALF;
      clk <= '0';
    end loop;
    report "PASS tb_classify_live: seed " & integer'image(SEED) & ", " & integer'image(SAMPLES) & " samples"
      severity note;
    finish(0);
  end process run;
end architecture sim;
