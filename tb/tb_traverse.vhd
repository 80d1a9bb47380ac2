-- tb_traverse: traverse (fpga/rtl/traverse.vhd) against the golden vectors traverse.*.hex.
--
-- Drives:  one vector a cycle with in_valid = 1, after the reset edge: pos_x pos_y pos_z
--          (SQ13.15) step_x step_y step_z (SQ3.15) lifetime cell_lo_x..z cell_hi_x..z
--          dims_x..z block_empty; widths from the DUT's ports.
-- Checks:  LAT cycles later, out_valid = 1 and action leaped pos_x_out pos_y_out pos_z_out
--          lifetime_out; a malformed line is one error and a cycle with in_valid = 0, whose
--          out_valid must be 0.
-- Latency: LAT = TRAVERSE_LATENCY (dp_pkg).
-- Usage:   ghdl -r --std=08 tb_traverse -gVECTORS=path/traverse.x.hex
library ieee;
use ieee.std_logic_1164.all;
use std.textio.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.tb_pkg.all;
use work.vec_io_pkg.all;

entity tb_traverse is
  generic (VECTORS : string := "traverse.hex");
end entity tb_traverse;

architecture sim of tb_traverse is
  constant TB  : string := "tb_traverse";
  constant LAT : positive := TRAVERSE_LATENCY;
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
  signal due : expect_t;  -- what the vector driven LAT cycles before expects
begin
  dut : entity work.traverse
    port map (clk => clk, rst => rst, in_valid => in_valid, pos => pos, step => step,
              lifetime => lifetime, cell_lo => cell_lo, cell_hi => cell_hi, dims => dims,
              block_empty => block_empty, out_valid => out_valid, action => action,
              leaped => leaped, pos_out => pos_out, lifetime_out => lifetime_out);

  run : process
    constant AXIS : string := "xyz";
    file f : text;
    variable l : line;
    variable lineno, errs, cycle : natural := 0;
    variable ok, compare : boolean;
    variable e : expect_t;
    variable i_pos : pos3_t;
    variable i_step : step3_t;
    variable i_life : std_logic_vector(lifetime'range);
    variable i_lo, i_hi, i_dims : grid3_t;
    variable i_empty : std_logic_vector(0 downto 0);
  begin
    open_vectors(f, VECTORS, TB);
    reset(clk, rst);
    loop
      next_line(f, l, lineno, ok);
      if ok then  -- a line, well formed or not: its inputs are driven
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
        e.lineno := lineno;
        pos <= i_pos;
        step <= i_step;
        lifetime <= i_life;
        cell_lo <= i_lo;
        cell_hi <= i_hi;
        dims <= i_dims;
        block_empty <= i_empty(0);
      end if;
      e.valid := ok;
      in_valid <= '1' when ok else '0';
      due <= transport e after LAT * PERIOD;
      wait for HALF;  -- clock low: this cycle's outputs are stable
      check_valid(cycle >= LAT, due.lineno, due.valid, out_valid, errs, compare);
      if compare then
        check(due.lineno, "action", due.action, action, errs);
        check(due.lineno, "leaped", due.leaped, leaped, errs);
        for a in 0 to 2 loop
          check(due.lineno, "pos_" & AXIS(a + 1) & "_out", due.pos(a), pos_out(a), errs);
        end loop;
        check(due.lineno, "lifetime_out", due.life, lifetime_out, errs);
      end if;
      exit when endfile(f) and cycle >= lineno + LAT - 1;
      edge(clk);
      cycle := cycle + 1;
    end loop;
    finish_run(TB, lineno, errs);
    wait;
  end process run;
end architecture sim;
