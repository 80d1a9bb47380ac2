-- File-driven testbench of interp against interp.*.hex, one vector a clock cycle.
--
-- Columns: frac_x frac_y frac_z (UQ0.15) v0..v7 (voxels, corner kx + 2 ky + 4 kz) in,
-- value (UQ8.8) out; widths from the DUT's ports. After one reset edge, vector n is
-- driven in cycle n with in_valid = 1; in cycle n + INTERP_LATENCY out_valid must be 1
-- and value must equal the file's (a malformed line is one error and a cycle with
-- in_valid = 0, whose out_valid must be 0). Usage:
--   ghdl -r --std=08 tb_interp -gVECTORS=path/interp.x.hex
library ieee;
use ieee.std_logic_1164.all;
use std.textio.all;

library work;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.vec_io_pkg.all;

entity tb_interp is
  generic (VECTORS : string := "interp.hex");
end entity tb_interp;

architecture sim of tb_interp is
  constant TB   : string := "tb_interp";
  constant LAT    : positive := INTERP_LATENCY;
  constant HALF : time := 5 ns;
  signal clk, rst, in_valid, out_valid : std_logic := '0';
  signal frac  : frac3_t := (others => (others => '0'));
  signal v     : voxel8_t := (others => (others => '0'));
  signal value : std_logic_vector(SIG_SAMPLE_VALUE_WIDTH - 1 downto 0);

  -- what cycle n expects, kept until cycle n + LAT
  type expect_t is record
    valid  : boolean;
    lineno : positive;
    value  : std_logic_vector(value'range);
  end record;
  type ring_t is array (0 to LAT) of expect_t;
begin
  dut : entity work.interp
    port map (clk => clk, rst => rst, in_valid => in_valid, frac => frac, v => v,
              out_valid => out_valid, value => value);

  run : process
    file f : text;
    variable l : line;
    variable lineno, errs, cycle : natural := 0;
    variable ok, more : boolean;
    variable fr : frac3_t;
    variable vv : voxel8_t;
    variable e : expect_t;
    variable ring : ring_t;
    constant AXIS : string := "xyz";
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
          read_col(l, a = 0, "frac_" & AXIS(a + 1), lineno, fr(a), ok, errs);
        end loop;
        for k in 0 to 7 loop
          read_col(l, false, "v" & integer'image(k), lineno, vv(k), ok, errs);
        end loop;
        read_col(l, false, "value", lineno, e.value, ok, errs);
        end_of_line(l, lineno, ok, errs);
        e.valid := ok;
        e.lineno := lineno;
        frac <= fr;
        v <= vv;
      end if;
      in_valid <= '1' when e.valid else '0';
      ring(cycle mod (LAT + 1)) := e;
      wait for HALF;  -- clock low: this cycle's outputs are stable
      if cycle >= LAT then
        e := ring((cycle - LAT) mod (LAT + 1));
        check(e.lineno, "out_valid", bits(e.valid), (0 => out_valid), errs);
        if e.valid then
          check(e.lineno, "value", e.value, value, errs);
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
