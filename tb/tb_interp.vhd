-- tb_interp: interp (fpga/rtl/interp.vhd) against the golden vectors interp.*.hex.
--
-- Drives:  one vector a cycle with in_valid = 1, after the reset edge: frac_x frac_y frac_z
--          (UQ0.15), v0..v7 (voxels, corner kx + 2 ky + 4 kz); widths from the DUT's ports.
-- Checks:  LAT cycles later, out_valid = 1 and value (UQ8.8); a malformed line is one error
--          and a cycle with in_valid = 0, whose out_valid must be 0.
-- Latency: LAT = INTERP_LATENCY (dp_pkg).
-- Usage:   ghdl -r --std=08 tb_interp -gVECTORS=path/interp.x.hex
library ieee;
use ieee.std_logic_1164.all;
use std.textio.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.tb_pkg.all;
use work.vec_io_pkg.all;

entity tb_interp is
  generic (VECTORS : string := "interp.hex");
end entity tb_interp;

architecture sim of tb_interp is
  constant TB  : string := "tb_interp";
  constant LAT : positive := INTERP_LATENCY;
  signal clk, rst, in_valid, out_valid : std_logic := '0';
  signal frac  : frac3_t := (others => (others => '0'));
  signal v     : voxel8_t := (others => (others => '0'));
  signal value : std_logic_vector(SIG_SAMPLE_VALUE_WIDTH - 1 downto 0);

  type expect_t is record
    valid  : boolean;
    lineno : positive;
    value  : std_logic_vector(value'range);
  end record;
  signal due : expect_t;  -- what the vector driven LAT cycles before expects
begin
  dut : entity work.interp
    port map (clk => clk, rst => rst, in_valid => in_valid, frac => frac, v => v,
              out_valid => out_valid, value => value);

  run : process
    constant AXIS : string := "xyz";
    file f : text;
    variable l : line;
    variable lineno, errs, cycle : natural := 0;
    variable ok, compare : boolean;
    variable e : expect_t;
    variable i_frac : frac3_t;
    variable i_v : voxel8_t;
  begin
    open_vectors(f, VECTORS, TB);
    reset(clk, rst);
    loop
      next_line(f, l, lineno, ok);
      if ok then  -- a line, well formed or not: its inputs are driven
        for a in 0 to 2 loop
          read_col(l, a = 0, "frac_" & AXIS(a + 1), lineno, i_frac(a), ok, errs);
        end loop;
        for k in 0 to 7 loop
          read_col(l, false, "v" & integer'image(k), lineno, i_v(k), ok, errs);
        end loop;
        read_col(l, false, "value", lineno, e.value, ok, errs);
        end_of_line(l, lineno, ok, errs);
        e.lineno := lineno;
        frac <= i_frac;
        v <= i_v;
      end if;
      e.valid := ok;
      in_valid <= '1' when ok else '0';
      due <= transport e after LAT * PERIOD;
      wait for HALF;  -- clock low: this cycle's outputs are stable
      check_valid(cycle >= LAT, due.lineno, due.valid, out_valid, errs, compare);
      if compare then
        check(due.lineno, "value", due.value, value, errs);
      end if;
      exit when endfile(f) and cycle >= lineno + LAT - 1;
      edge(clk);
      cycle := cycle + 1;
    end loop;
    finish_run(TB, lineno, errs);
    wait;
  end process run;
end architecture sim;
