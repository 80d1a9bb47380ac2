-- tb_classify: classify (fpga/rtl/classify.vhd) against the golden vectors classify.*.hex and
-- the table image classify.SOURCE.tf.hex (line i = entry i: r g b a).
--
-- Drives:  after the reset edge, the table through the table port, one entry a cycle; then
--          one vector a cycle with in_valid = 1: value (UQ8.8); widths from the DUT's ports.
-- Checks:  LAT cycles later, out_valid = 1 and r g b a (UQ1.15); a malformed line is one
--          error and a cycle with in_valid = 0, whose out_valid must be 0. A table that is
--          malformed or not exactly 2^8 lines is a failure.
-- Latency: LAT = CLASSIFY_LATENCY (dp_pkg).
-- Usage:   ghdl -r --std=08 tb_classify -gVECTORS=path/classify.x.hex -gTABLE=path/classify.x.tf.hex
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use std.textio.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.tb_pkg.all;
use work.vec_io_pkg.all;

entity tb_classify is
  generic (VECTORS : string := "classify.hex"; TABLE : string := "classify.tf.hex");
end entity tb_classify;

architecture sim of tb_classify is
  constant TB  : string := "tb_classify";
  constant LAT : positive := CLASSIFY_LATENCY;
  signal clk, rst, in_valid, out_valid, tf_we : std_logic := '0';
  signal tf_addr : std_logic_vector(VOXEL_BITS - 1 downto 0) := (others => '0');
  signal tf_data, rgba : rgba4_t := (others => (others => '0'));
  signal value : std_logic_vector(SIG_SAMPLE_VALUE_WIDTH - 1 downto 0) := (others => '0');

  type expect_t is record
    valid  : boolean;
    lineno : positive;
    rgba   : rgba4_t;
  end record;
  signal due : expect_t;  -- what the vector driven LAT cycles before expects
begin
  dut : entity work.classify
    port map (clk => clk, rst => rst, tf_we => tf_we, tf_addr => tf_addr, tf_data => tf_data,
              in_valid => in_valid, value => value, out_valid => out_valid, rgba => rgba);

  run : process
    constant CH : string := "rgba";
    file f, t : text;
    variable l : line;
    variable lineno, errs, cycle, entries : natural := 0;
    variable ok, compare : boolean;
    variable e : expect_t;
    variable i_value : std_logic_vector(value'range);
    variable d : rgba4_t;
  begin
    open_vectors(f, VECTORS, TB);
    open_vectors(t, TABLE, TB);
    reset(clk, rst);
    -- the table, one entry a cycle
    while not endfile(t) loop
      next_line(t, l, entries, ok);
      for k in 0 to 3 loop
        read_col(l, k = 0, "table " & CH(k + 1), entries, d(k), ok, errs);
      end loop;
      end_of_line(l, entries, ok, errs);
      exit when not ok or entries > 2 ** VOXEL_BITS;
      tf_we <= '1';
      tf_addr <= std_logic_vector(to_unsigned(entries - 1, VOXEL_BITS));
      tf_data <= d;
      tick(clk);
    end loop;
    tf_we <= '0';
    if errs /= 0 or entries /= 2 ** VOXEL_BITS then
      report TABLE & ": " & integer'image(entries) & " entries read, " &
        integer'image(2 ** VOXEL_BITS) & " well-formed ones needed" severity error;
      finish_run(TB, 0, 1);
    end if;
    loop
      next_line(f, l, lineno, ok);
      if ok then  -- a line, well formed or not: its inputs are driven
        read_col(l, true, "value", lineno, i_value, ok, errs);
        for k in 0 to 3 loop
          read_col(l, false, CH(k + 1 to k + 1), lineno, e.rgba(k), ok, errs);
        end loop;
        end_of_line(l, lineno, ok, errs);
        e.lineno := lineno;
        value <= i_value;
      end if;
      e.valid := ok;
      in_valid <= '1' when ok else '0';
      due <= transport e after LAT * PERIOD;
      wait for HALF;  -- clock low: this cycle's outputs are stable
      check_valid(cycle >= LAT, due.lineno, due.valid, out_valid, errs, compare);
      if compare then
        for k in 0 to 3 loop
          check(due.lineno, CH(k + 1 to k + 1), due.rgba(k), rgba(k), errs);
        end loop;
      end if;
      exit when endfile(f) and cycle >= lineno + LAT - 1;
      edge(clk);
      cycle := cycle + 1;
    end loop;
    finish_run(TB, lineno, errs);
    wait;
  end process run;
end architecture sim;
