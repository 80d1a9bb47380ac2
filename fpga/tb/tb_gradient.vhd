-- File-driven testbench of gradient against gradient.*.hex, one vector a clock cycle.
--
-- Columns: frac_x frac_y frac_z (UQ0.15), dx0..dx7 dy0..dy7 dz0..dz7 (central differences,
-- corner kx + 2 ky + 4 kz), gs_x gs_y gs_z (UQ1.15) in; grad_x grad_y grad_z (SQ8.8) out;
-- widths from the DUT's ports. After one reset edge, vector n is driven in cycle n with
-- in_valid = 1; in cycle n + GRADIENT_LATENCY out_valid must be 1 and the gradient must
-- equal the file's (a malformed line is one error and a cycle with
-- in_valid = 0, whose out_valid must be 0). Usage:
--   ghdl -r --std=08 tb_gradient -gVECTORS=path/gradient.x.hex
library ieee;
use ieee.std_logic_1164.all;
use std.textio.all;

library work;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.vec_io_pkg.all;

entity tb_gradient is
  generic (VECTORS : string := "gradient.hex");
end entity tb_gradient;

architecture sim of tb_gradient is
  constant TB   : string := "tb_gradient";
  constant LAT    : positive := GRADIENT_LATENCY;
  constant HALF : time := 5 ns;
  signal clk, rst, in_valid, out_valid : std_logic := '0';
  signal frac  : frac3_t := (others => (others => '0'));
  signal d     : diff24_t := (others => (others => (others => '0')));
  signal gs    : gscale3_t := (others => (others => '0'));
  signal grad  : grad3_t;

  -- what cycle n expects, kept until cycle n + LAT
  type expect_t is record
    valid  : boolean;
    lineno : positive;
    grad   : grad3_t;
  end record;
  type ring_t is array (0 to LAT) of expect_t;
begin
  dut : entity work.gradient
    port map (clk => clk, rst => rst, in_valid => in_valid, frac => frac, d => d,
              gs => gs, out_valid => out_valid, grad => grad);

  run : process
    file f : text;
    variable l : line;
    variable lineno, errs, cycle : natural := 0;
    variable ok, more : boolean;
    variable fr : frac3_t;
    variable dd : diff24_t;
    variable g : gscale3_t;
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
        for a in 0 to 2 loop
          for k in 0 to 7 loop
            read_col(l, false, "d" & AXIS(a + 1) & integer'image(k), lineno, dd(a)(k), ok, errs);
          end loop;
        end loop;
        for a in 0 to 2 loop
          read_col(l, false, "gs_" & AXIS(a + 1), lineno, g(a), ok, errs);
        end loop;
        for a in 0 to 2 loop
          read_col(l, false, "grad_" & AXIS(a + 1), lineno, e.grad(a), ok, errs);
        end loop;
        end_of_line(l, lineno, ok, errs);
        e.valid := ok;
        e.lineno := lineno;
        frac <= fr;
        d <= dd;
        gs <= g;
      end if;
      in_valid <= '1' when e.valid else '0';
      ring(cycle mod (LAT + 1)) := e;
      wait for HALF;  -- clock low: this cycle's outputs are stable
      if cycle >= LAT then
        e := ring((cycle - LAT) mod (LAT + 1));
        check(e.lineno, "out_valid", bits(e.valid), (0 => out_valid), errs);
        if e.valid then
          for a in 0 to 2 loop
            check(e.lineno, "grad_" & AXIS(a + 1), e.grad(a), grad(a), errs);
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
