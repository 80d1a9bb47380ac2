-- tb_gradient: gradient (fpga/rtl/gradient.vhd) against the golden vectors gradient.*.hex.
--
-- Drives:  one vector a cycle with in_valid = 1, after the reset edge: frac_x frac_y frac_z
--          (UQ0.15), dx0..dx7 dy0..dy7 dz0..dz7 (central differences, corner kx + 2 ky +
--          4 kz), gs_x gs_y gs_z (UQ1.15); widths from the DUT's ports.
-- Checks:  LAT cycles later, out_valid = 1 and grad_x grad_y grad_z (SQ8.8); a malformed line
--          is one error and a cycle with in_valid = 0, whose out_valid must be 0.
-- Latency: LAT = GRADIENT_LATENCY (dp_pkg).
-- Usage:   ghdl -r --std=08 tb_gradient -gVECTORS=path/gradient.x.hex
library ieee;
use ieee.std_logic_1164.all;
use std.textio.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.tb_pkg.all;
use work.vec_io_pkg.all;

entity tb_gradient is
  generic (VECTORS : string := "gradient.hex");
end entity tb_gradient;

architecture sim of tb_gradient is
  constant TB  : string := "tb_gradient";
  constant LAT : positive := GRADIENT_LATENCY;
  signal clk, rst, in_valid, out_valid : std_logic := '0';
  signal frac : frac3_t := (others => (others => '0'));
  signal d    : diff24_t := (others => (others => (others => '0')));
  signal gs   : gscale3_t := (others => (others => '0'));
  signal grad : grad3_t;

  type expect_t is record
    valid  : boolean;
    lineno : positive;
    grad   : grad3_t;
  end record;
  signal due : expect_t;  -- what the vector driven LAT cycles before expects
begin
  dut : entity work.gradient
    port map (clk => clk, rst => rst, in_valid => in_valid, frac => frac, d => d,
              gs => gs, out_valid => out_valid, grad => grad);

  run : process
    constant AXIS : string := "xyz";
    file f : text;
    variable l : line;
    variable lineno, errs, cycle : natural := 0;
    variable ok, compare : boolean;
    variable e : expect_t;
    variable i_frac : frac3_t;
    variable i_d : diff24_t;
    variable i_gs : gscale3_t;
  begin
    open_vectors(f, VECTORS, TB);
    reset(clk, rst);
    loop
      next_line(f, l, lineno, ok);
      if ok then  -- a line, well formed or not: its inputs are driven
        for a in 0 to 2 loop
          read_col(l, a = 0, "frac_" & AXIS(a + 1), lineno, i_frac(a), ok, errs);
        end loop;
        for a in 0 to 2 loop
          for k in 0 to 7 loop
            read_col(l, false, "d" & AXIS(a + 1) & integer'image(k), lineno, i_d(a)(k), ok, errs);
          end loop;
        end loop;
        for a in 0 to 2 loop
          read_col(l, false, "gs_" & AXIS(a + 1), lineno, i_gs(a), ok, errs);
        end loop;
        for a in 0 to 2 loop
          read_col(l, false, "grad_" & AXIS(a + 1), lineno, e.grad(a), ok, errs);
        end loop;
        end_of_line(l, lineno, ok, errs);
        e.lineno := lineno;
        frac <= i_frac;
        d <= i_d;
        gs <= i_gs;
      end if;
      e.valid := ok;
      in_valid <= '1' when ok else '0';
      due <= transport e after LAT * PERIOD;
      wait for HALF;  -- clock low: this cycle's outputs are stable
      check_valid(cycle >= LAT, due.lineno, due.valid, out_valid, errs, compare);
      if compare then
        for a in 0 to 2 loop
          check(due.lineno, "grad_" & AXIS(a + 1), due.grad(a), grad(a), errs);
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
