-- tb_composite: composite (fpga/rtl/composite.vhd) against the golden vectors composite.*.hex.
--
-- Drives:  one vector a cycle with in_valid = 1, after the reset edge: w opa rgb_r rgb_g rgb_b
--          alpha c_r c_g c_b shadow a_max; widths from the DUT's ports.
-- Checks:  LAT cycles later, out_valid = 1 and rgb_r_out rgb_g_out rgb_b_out opa_out done sat;
--          a malformed line is one error and a cycle with in_valid = 0, whose out_valid must
--          be 0.
-- Latency: LAT = COMPOSITE_LATENCY (dp_pkg).
-- Usage:   ghdl -r --std=08 tb_composite -gVECTORS=path/composite.x.hex
library ieee;
use ieee.std_logic_1164.all;
use std.textio.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.tb_pkg.all;
use work.vec_io_pkg.all;

entity tb_composite is
  generic (VECTORS : string := "composite.hex");
end entity tb_composite;

architecture sim of tb_composite is
  constant TB  : string := "tb_composite";
  constant LAT : positive := COMPOSITE_LATENCY;
  signal clk, rst, in_valid, out_valid, shadow, done : std_logic := '0';
  signal w     : std_logic_vector(RAY_PACKET_CONTRIBUTION_WIDTH - 1 downto 0) := (others => '0');
  signal opa, a_max, opa_out : std_logic_vector(SIG_MAX_OPACITY_WIDTH - 1 downto 0) := (others => '0');
  signal alpha : std_logic_vector(SIG_TF_RGBA_WIDTH - 1 downto 0) := (others => '0');
  signal rgb, rgb_out : rgb3_t := (others => (others => '0'));
  signal c     : shaded3_t := (others => (others => '0'));
  signal sat   : std_logic_vector(1 downto 0);

  type expect_t is record
    valid  : boolean;
    lineno : positive;
    rgb    : rgb3_t;
    opa    : std_logic_vector(opa_out'range);
    done   : std_logic_vector(0 downto 0);
    sat    : std_logic_vector(sat'range);
  end record;
  signal due : expect_t;  -- what the vector driven LAT cycles before expects
begin
  dut : entity work.composite
    port map (clk => clk, rst => rst, in_valid => in_valid, w => w, opa => opa, rgb => rgb,
              alpha => alpha, c => c, shadow => shadow, a_max => a_max,
              out_valid => out_valid, rgb_out => rgb_out, opa_out => opa_out, done => done,
              sat => sat);

  run : process
    constant CH : string := "rgb";
    file f : text;
    variable l : line;
    variable lineno, errs, cycle : natural := 0;
    variable ok, compare : boolean;
    variable e : expect_t;
    variable i_w : std_logic_vector(w'range);
    variable i_opa, i_amax : std_logic_vector(opa'range);
    variable i_alpha : std_logic_vector(alpha'range);
    variable i_rgb : rgb3_t;
    variable i_c : shaded3_t;
    variable i_shadow : std_logic_vector(0 downto 0);
  begin
    open_vectors(f, VECTORS, TB);
    reset(clk, rst);
    loop
      next_line(f, l, lineno, ok);
      if ok then  -- a line, well formed or not: its inputs are driven
        read_col(l, true,  "w", lineno, i_w, ok, errs);
        read_col(l, false, "opa", lineno, i_opa, ok, errs);
        for k in 0 to 2 loop
          read_col(l, false, "rgb_" & CH(k + 1), lineno, i_rgb(k), ok, errs);
        end loop;
        read_col(l, false, "alpha", lineno, i_alpha, ok, errs);
        for k in 0 to 2 loop
          read_col(l, false, "c_" & CH(k + 1), lineno, i_c(k), ok, errs);
        end loop;
        read_col(l, false, "shadow", lineno, i_shadow, ok, errs);
        read_col(l, false, "a_max", lineno, i_amax, ok, errs);
        for k in 0 to 2 loop
          read_col(l, false, "rgb_" & CH(k + 1) & "_out", lineno, e.rgb(k), ok, errs);
        end loop;
        read_col(l, false, "opa_out", lineno, e.opa, ok, errs);
        read_col(l, false, "done", lineno, e.done, ok, errs);
        read_col(l, false, "sat", lineno, e.sat, ok, errs);
        end_of_line(l, lineno, ok, errs);
        e.lineno := lineno;
        w <= i_w;
        opa <= i_opa;
        rgb <= i_rgb;
        alpha <= i_alpha;
        c <= i_c;
        shadow <= i_shadow(0);
        a_max <= i_amax;
      end if;
      e.valid := ok;
      in_valid <= '1' when ok else '0';
      due <= transport e after LAT * PERIOD;
      wait for HALF;  -- clock low: this cycle's outputs are stable
      check_valid(cycle >= LAT, due.lineno, due.valid, out_valid, errs, compare);
      if compare then
        for k in 0 to 2 loop
          check(due.lineno, "rgb_" & CH(k + 1) & "_out", due.rgb(k), rgb_out(k), errs);
        end loop;
        check(due.lineno, "opa_out", due.opa, opa_out, errs);
        check(due.lineno, "done", due.done, (0 => done), errs);
        check(due.lineno, "sat", due.sat, sat, errs);
      end if;
      exit when endfile(f) and cycle >= lineno + LAT - 1;
      edge(clk);
      cycle := cycle + 1;
    end loop;
    finish_run(TB, lineno, errs);
    wait;
  end process run;
end architecture sim;
