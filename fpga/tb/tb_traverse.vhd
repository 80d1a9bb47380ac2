-- File-driven testbench of traverse against traverse.*.hex, one vector a clock cycle.
--
-- Columns: pos_x pos_y pos_z (SQ10.15) step_x step_y step_z (SQ3.15) lifetime cell_lo_x..z
-- cell_hi_x..z dims_x..z block_empty in; action leaped pos_x_out pos_y_out pos_z_out
-- lifetime_out out; widths from the DUT's ports. After one reset edge, vector n is driven
-- in cycle n with in_valid = 1; in cycle n + TRAVERSE_LATENCY out_valid must be 1 and every
-- output equal the file's (a malformed line is one error and a cycle with in_valid = 0,
-- whose out_valid must be 0). Usage:
--   ghdl -r --std=08 tb_traverse -gVECTORS=path/traverse.x.hex
library ieee;
use ieee.std_logic_1164.all;
use std.textio.all;

library work;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.vec_io_pkg.all;

entity tb_traverse is
  generic (VECTORS : string := "traverse.hex");
end entity tb_traverse;

architecture sim of tb_traverse is
  constant TB   : string := "tb_traverse";
  constant LAT  : positive := TRAVERSE_LATENCY;
  constant HALF : time := 5 ns;
  constant AXIS : string := "xyz";
  signal clk, rst, in_valid, out_valid, block_empty : std_logic := '0';
  signal pos, pos_out : pos3_t := (others => (others => '0'));
  signal step : step3_t := (others => (others => '0'));
  signal lifetime, lifetime_out : std_logic_vector(RAY_PACKET_LIFETIME_WIDTH - 1 downto 0) := (others => '0');
  signal cell_lo, cell_hi, dims : grid3_t := (others => (others => '0'));
  signal action : std_logic_vector(1 downto 0);
  signal leaped : std_logic_vector(LEAPED_BITS - 1 downto 0);

  type expect_t is record
    valid  : boolean;
    lineno : positive;
    action : std_logic_vector(action'range);
    leaped : std_logic_vector(leaped'range);
    pos    : pos3_t;
    life   : std_logic_vector(lifetime'range);
  end record;
  type ring_t is array (0 to LAT) of expect_t;
begin
  dut : entity work.traverse
    port map (clk => clk, rst => rst, in_valid => in_valid, pos => pos, step => step,
              lifetime => lifetime, cell_lo => cell_lo, cell_hi => cell_hi, dims => dims,
              block_empty => block_empty, out_valid => out_valid, action => action,
              leaped => leaped, pos_out => pos_out, lifetime_out => lifetime_out);

  run : process
    file f : text;
    variable l : line;
    variable lineno, errs, cycle : natural := 0;
    variable ok, more : boolean;
    variable i_pos : pos3_t;
    variable i_step : step3_t;
    variable i_life : std_logic_vector(lifetime'range);
    variable i_lo, i_hi, i_dims : grid3_t;
    variable i_empty : std_logic_vector(0 downto 0);
    variable e : expect_t;
    variable ring : ring_t;
  begin
    open_vectors(f, VECTORS, TB);
    rst <= '1';
    wait for HALF;
    clk <= '1';
    wait for HALF;
    clk <= '0';
    rst <= '0';
    loop
      more := not endfile(f);
      e.valid := false;
      if more then
        readline(f, l);
        lineno := lineno + 1;
        ok := true;
        for a in 0 to 2 loop
          read_col(l, a = 0, "pos_" & AXIS(a + 1), lineno, i_pos(a), ok, errs);
        end loop;
        for a in 0 to 2 loop
          read_col(l, false, "step_" & AXIS(a + 1), lineno, i_step(a), ok, errs);
        end loop;
        read_col(l, false, "lifetime", lineno, i_life, ok, errs);
        for a in 0 to 2 loop
          read_col(l, false, "cell_lo_" & AXIS(a + 1), lineno, i_lo(a), ok, errs);
        end loop;
        for a in 0 to 2 loop
          read_col(l, false, "cell_hi_" & AXIS(a + 1), lineno, i_hi(a), ok, errs);
        end loop;
        for a in 0 to 2 loop
          read_col(l, false, "dims_" & AXIS(a + 1), lineno, i_dims(a), ok, errs);
        end loop;
        read_col(l, false, "block_empty", lineno, i_empty, ok, errs);
        read_col(l, false, "action", lineno, e.action, ok, errs);
        read_col(l, false, "leaped", lineno, e.leaped, ok, errs);
        for a in 0 to 2 loop
          read_col(l, false, "pos_" & AXIS(a + 1) & "_out", lineno, e.pos(a), ok, errs);
        end loop;
        read_col(l, false, "lifetime_out", lineno, e.life, ok, errs);
        end_of_line(l, lineno, ok, errs);
        e.valid := ok;
        e.lineno := lineno;
        pos <= i_pos;
        step <= i_step;
        lifetime <= i_life;
        cell_lo <= i_lo;
        cell_hi <= i_hi;
        dims <= i_dims;
        block_empty <= i_empty(0);
      end if;
      in_valid <= '1' when e.valid else '0';
      ring(cycle mod (LAT + 1)) := e;
      wait for HALF;  -- clock low: this cycle's outputs are stable
      if cycle >= LAT then
        e := ring((cycle - LAT) mod (LAT + 1));
        check(e.lineno, "out_valid", bits(e.valid), (0 => out_valid), errs);
        if e.valid then
          check(e.lineno, "action", e.action, action, errs);
          check(e.lineno, "leaped", e.leaped, leaped, errs);
          for a in 0 to 2 loop
            check(e.lineno, "pos_" & AXIS(a + 1) & "_out", e.pos(a), pos_out(a), errs);
          end loop;
          check(e.lineno, "lifetime_out", e.life, lifetime_out, errs);
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
