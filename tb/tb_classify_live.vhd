-- tb_classify_live: classify (fpga/rtl/classify.vhd) against the C model running beside it
-- (c5ref_cl_*, the model's table lookup; docs/vectors.md, "The model inside the simulator").
--
-- Drives:  after the reset edge, a transfer-function table drawn from SEED (entries 0, 1.0 or
--          random) into the DUT's table and the model's, one entry a cycle; then one sample
--          value a cycle, SAMPLES of them (random, on an entry, half-way between two, or
--          above 255.0 where the lookup clamps).
-- Checks:  LAT cycles later, out_valid = 1 and r g b a = the model's; the first difference
--          ends the run: "FAIL tb_classify_live: seed S sample N: rgba(C): model X, VHDL Y".
-- Latency: LAT = CLASSIFY_LATENCY (dp_pkg).
-- Usage:   ghdl -r --std=08 tb_classify_live -gSEED=1 -gSAMPLES=5000 (./libc5ref.so beside)
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.c5ref_pkg.all;
use work.tb_pkg.all;

entity tb_classify_live is
  generic (SEED : positive := 1; SAMPLES : positive := 5000);
end entity tb_classify_live;

architecture sim of tb_classify_live is
  constant TB  : string := "tb_classify_live";
  constant AT  : string := live_at(TB, SEED, "sample");
  constant LAT : positive := CLASSIFY_LATENCY;
  signal clk, rst, in_valid, out_valid, tf_we : std_logic := '0';
  signal tf_addr : std_logic_vector(VOXEL_BITS - 1 downto 0) := (others => '0');
  signal tf_data, rgba : rgba4_t := (others => (others => '0'));
  signal value : std_logic_vector(SIG_SAMPLE_VALUE_WIDTH - 1 downto 0) := (others => '0');
  signal due : integer_vector(0 to 3);  -- the model's r g b a, LAT cycles after its sample
begin
  dut : entity work.classify
    port map (clk => clk, rst => rst, tf_we => tf_we, tf_addr => tf_addr, tf_data => tf_data,
              in_valid => in_valid, value => value, out_valid => out_valid, rgba => rgba);

  run : process
    constant ONE : integer := 2 ** SIG_TF_RGBA_FRAC;
    constant VMAX : integer := 2 ** SIG_SAMPLE_VALUE_WIDTH - 1;
    variable rnd : random_t;
    variable x, rc : integer;
    variable e : integer_vector(0 to 3);
  begin
    rnd.seed(SEED);
    reset(clk, rst);
    for i in 0 to 255 loop  -- the table, one entry a cycle
      for ch in 0 to 3 loop
        case rnd.pick(4) is
          when 0 => x := 0;
          when 1 => x := ONE;
          when others => x := rnd.pick(ONE + 1);
        end case;
        tf_data(ch) <= std_logic_vector(to_unsigned(x, SIG_TF_RGBA_WIDTH));
        rc := c5ref_cl_table(i, ch, x);
      end loop;
      tf_we <= '1';
      tf_addr <= std_logic_vector(to_unsigned(i, VOXEL_BITS));
      tick(clk);
    end loop;
    tf_we <= '0';
    for n in 0 to SAMPLES + LAT - 1 loop
      if n < SAMPLES then
        case rnd.pick(5) is
          when 0 => x := 256 * rnd.pick(256);                -- on an entry
          when 1 => x := 256 * rnd.pick(256) + 128;          -- half-way: the rounding tie
          when 2 => x := 65280 + rnd.pick(VMAX - 65280 + 1); -- 255.0 and above: clamped
          when others => x := rnd.pick(VMAX + 1);
        end case;
        value <= std_logic_vector(to_unsigned(x, SIG_SAMPLE_VALUE_WIDTH));
        for ch in 0 to 3 loop
          e(ch) := c5ref_cl_run(x, ch);
        end loop;
        due <= transport e after LAT * PERIOD;
      end if;
      in_valid <= '1' when n < SAMPLES else '0';
      wait for HALF;  -- clock low: this cycle's outputs are stable
      if n >= LAT then
        live_expect(AT, n - LAT, "out_valid", 1, live_bit(out_valid));
        for ch in 0 to 3 loop
          live_expect(AT, n - LAT, "rgba(" & integer'image(ch) & ")", due(ch), to_integer(unsigned(rgba(ch))));
        end loop;
      end if;
      edge(clk);
    end loop;
    live_pass(TB, SEED, integer'image(SAMPLES) & " samples");
  end process run;
end architecture sim;
