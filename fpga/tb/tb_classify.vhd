-- File-driven testbench of classify against classify.*.hex, one vector a clock cycle,
-- after the table image (classify.SOURCE.tf.hex: line i = entry i, r g b a) is written
-- through the table port, one entry a cycle.
--
-- Columns: value (UQ8.8) in; r g b a (UQ1.15) out; widths from the DUT's ports. After
-- one reset edge and the table, vector n is driven in cycle n with in_valid = 1; in cycle
-- n + CLASSIFY_LATENCY out_valid must be 1 and r g b a equal the file's (a malformed line
-- is one error and a cycle with in_valid = 0, whose out_valid must be 0). A table that is
-- malformed or not exactly 2^8 lines is a failure. Usage:
--   ghdl -r --std=08 tb_classify -gVECTORS=path/classify.x.hex -gTABLE=path/classify.x.tf.hex
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use std.textio.all;

library work;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.vec_io_pkg.all;

entity tb_classify is
  generic (VECTORS : string := "classify.hex"; TABLE : string := "classify.tf.hex");
end entity tb_classify;

architecture sim of tb_classify is
  constant TB   : string := "tb_classify";
  constant LAT  : positive := CLASSIFY_LATENCY;
  constant HALF : time := 5 ns;
  constant CH   : string := "rgba";
  signal clk, rst, in_valid, out_valid, tf_we : std_logic := '0';
  signal tf_addr : std_logic_vector(VOXEL_BITS - 1 downto 0) := (others => '0');
  signal tf_data, rgba : rgba4_t := (others => (others => '0'));
  signal value : std_logic_vector(SIG_SAMPLE_VALUE_WIDTH - 1 downto 0) := (others => '0');

  type expect_t is record
    valid  : boolean;
    lineno : positive;
    rgba   : rgba4_t;
  end record;
  type ring_t is array (0 to LAT) of expect_t;
begin
  dut : entity work.classify
    port map (clk => clk, rst => rst, tf_we => tf_we, tf_addr => tf_addr, tf_data => tf_data,
              in_valid => in_valid, value => value, out_valid => out_valid, rgba => rgba);

  run : process
    file f, t : text;
    variable l : line;
    variable lineno, errs, cycle, entries : natural := 0;
    variable ok, more : boolean;
    variable i_value : std_logic_vector(value'range);
    variable d : rgba4_t;
    variable e : expect_t;
    variable ring : ring_t;

    procedure tick is
    begin
      wait for HALF;
      clk <= '1';
      wait for HALF;
      clk <= '0';
    end procedure tick;
  begin
    open_vectors(f, VECTORS, TB);
    open_vectors(t, TABLE, TB);
    rst <= '1';
    tick;
    rst <= '0';
    -- the table, one entry a cycle
    while not endfile(t) loop
      readline(t, l);
      entries := entries + 1;
      ok := true;
      for k in 0 to 3 loop
        read_col(l, k = 0, "table " & CH(k + 1), entries, d(k), ok, errs);
      end loop;
      end_of_line(l, entries, ok, errs);
      exit when not ok or entries > 2 ** VOXEL_BITS;
      tf_we <= '1';
      tf_addr <= std_logic_vector(to_unsigned(entries - 1, VOXEL_BITS));
      tf_data <= d;
      tick;
    end loop;
    tf_we <= '0';
    if errs /= 0 or entries /= 2 ** VOXEL_BITS then
      report TABLE & ": " & integer'image(entries) & " entries read, " &
        integer'image(2 ** VOXEL_BITS) & " well-formed ones needed" severity error;
      finish_run(TB, 0, 1);
    end if;
    loop
      more := not endfile(f);
      e.valid := false;
      if more then
        readline(f, l);
        lineno := lineno + 1;
        ok := true;
        read_col(l, true, "value", lineno, i_value, ok, errs);
        for k in 0 to 3 loop
          read_col(l, false, CH(k + 1 to k + 1), lineno, e.rgba(k), ok, errs);
        end loop;
        end_of_line(l, lineno, ok, errs);
        e.valid := ok;
        e.lineno := lineno;
        value <= i_value;
      end if;
      in_valid <= '1' when e.valid else '0';
      ring(cycle mod (LAT + 1)) := e;
      wait for HALF;  -- clock low: this cycle's outputs are stable
      if cycle >= LAT then
        e := ring((cycle - LAT) mod (LAT + 1));
        check(e.lineno, "out_valid", bits(e.valid), (0 => out_valid), errs);
        if e.valid then
          for k in 0 to 3 loop
            check(e.lineno, CH(k + 1 to k + 1), e.rgba(k), rgba(k), errs);
          end loop;
        end if;
      end if;
      exit when not more and cycle >= lineno + LAT - 1;
      clk <= '1';
      wait for HALF;
      clk <= '0';
      cycle := cycle + 1;
    end loop;
    finish_run(TB, lineno, errs);
    wait;
  end process run;
end architecture sim;
