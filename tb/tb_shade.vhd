-- tb_shade: shade (fpga/rtl/shade.vhd) against the golden vectors shade.*.hex, the register
-- image shade.SOURCE.regs.hex (one 32-bit value a line) and the power table image
-- shade.SOURCE.pow.hex (2^10 + 1 lines).
--
-- Drives:  after the reset edge, the registers and the power table through the
--          configuration ports, one a cycle; then one sample at a time with in_valid while
--          in_ready = 1: grad_x grad_y grad_z (SQ8.8) tf_r tf_g tf_b (UQ1.15) gpos_x gpos_y
--          gpos_z (SQ13.15) dir_x dir_y dir_z (SQ1.14).
-- Checks:  when out_valid comes, rgb_r rgb_g rgb_b (UQ4.12) sat and the latency. A malformed
--          line is one error and is skipped; no out_valid within the latency bound ends the
--          run.
-- Latency: exactly SHADE_FLAT_CYCLES when g = 0, else within the bounds shade.vhd's
--          formula gives for these registers (every light skipped at N.L <= 0 .. every light
--          reaching the table); the latencies seen are reported.
-- Usage:   ghdl -r --std=08 tb_shade -gVECTORS=shade.x.hex -gREGS=shade.x.regs.hex -gPOW=shade.x.pow.hex
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use std.textio.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.tb_pkg.all;
use work.vec_io_pkg.all;

entity tb_shade is
  generic (VECTORS : string := "shade.hex"; REGS : string := "shade.regs.hex";
           POW : string := "shade.pow.hex");
end entity tb_shade;

architecture sim of tb_shade is
  constant TB   : string := "tb_shade";
  signal clk, rst, in_valid, in_ready, out_valid, reg_we, pow_we : std_logic := '0';
  signal reg_addr : std_logic_vector(6 downto 0) := (others => '0');
  signal reg_data : std_logic_vector(31 downto 0) := (others => '0');
  signal pow_addr : std_logic_vector(POW_ADDR_BITS - 1 downto 0) := (others => '0');
  signal pow_data : std_logic_vector(SIG_SPEC_POW_WIDTH - 1 downto 0) := (others => '0');
  signal grad : grad3_t := (others => (others => '0'));
  signal tf   : tf3_t := (others => (others => '0'));
  signal gpos : gpos3_t := (others => (others => '0'));
  signal dir  : dir3_t := (others => (others => '0'));
  signal rgb  : shaded3_t;
  signal sat  : std_logic_vector(2 downto 0);
begin
  dut : entity work.shade
    port map (clk => clk, rst => rst, reg_we => reg_we, reg_addr => reg_addr,
              reg_data => reg_data, pow_we => pow_we, pow_addr => pow_addr,
              pow_data => pow_data, in_valid => in_valid, in_ready => in_ready,
              grad => grad, tf => tf, gpos => gpos, dir => dir, out_valid => out_valid,
              rgb => rgb, sat => sat);

  run : process
    constant AXIS : string := "xyz";
    constant CH   : string := "rgb";
    file f, rf, pf : text;
    variable l : line;
    variable lineno, errs, n : natural := 0;
    variable ok : boolean;
    variable i_grad : grad3_t;
    variable i_tf : tf3_t;
    variable i_gpos : gpos3_t;
    variable i_dir : dir3_t;
    variable e_rgb : shaded3_t;
    variable e_sat : std_logic_vector(2 downto 0);
    variable rv : std_logic_vector(31 downto 0);
    variable pv : std_logic_vector(SIG_SPEC_POW_WIDTH - 1 downto 0);
    type regs_t is array (0 to SHADE_REGS - 1) of integer;
    variable r : regs_t;
    variable m2 : signed(2 * SIG_GRADIENT_WIDTH + 1 downto 0);  -- |g|^2, 16 fraction bits
    variable lat, lat_min, lat_max, seen_min, seen_max : integer;

    -- one configuration image: each line one column `name` of w'length bits
    procedure bad_image(path : string; lines, want : natural) is
    begin
      report path & ": " & integer'image(lines) & " lines read, " & integer'image(want) &
        " well-formed ones needed" severity error;
      finish_run(TB, 0, 1);
    end procedure bad_image;
  begin
    open_vectors(f, VECTORS, TB);
    open_vectors(rf, REGS, TB);
    open_vectors(pf, POW, TB);
    reset(clk, rst);
    -- the registers
    n := 0;
    while not endfile(rf) loop
      next_line(rf, l, n, ok);
      read_col(l, true, "register", n, rv, ok, errs);
      end_of_line(l, n, ok, errs);
      exit when not ok or n > SHADE_REGS;
      r(n - 1) := to_integer(signed(rv));
      reg_we <= '1';
      reg_addr <= std_logic_vector(to_unsigned(n - 1, reg_addr'length));
      reg_data <= rv;
      tick(clk);
    end loop;
    reg_we <= '0';
    if errs /= 0 or n /= SHADE_REGS then
      bad_image(REGS, n, SHADE_REGS);
    end if;
    -- the power table
    n := 0;
    while not endfile(pf) loop
      next_line(pf, l, n, ok);
      read_col(l, true, "spec_pow", n, pv, ok, errs);
      end_of_line(l, n, ok, errs);
      exit when not ok or n > 2 ** POW_TABLE_BITS + 1;
      pow_we <= '1';
      pow_addr <= std_logic_vector(to_unsigned(n - 1, pow_addr'length));
      pow_data <= pv;
      tick(clk);
    end loop;
    pow_we <= '0';
    if errs /= 0 or n /= 2 ** POW_TABLE_BITS + 1 then
      bad_image(POW, n, 2 ** POW_TABLE_BITS + 1);
    end if;
    -- the latency bounds of these registers (shade.vhd's formula)
    lat_min := SHADE_NORM_CYCLES + 6;
    lat_max := lat_min;
    for i in 0 to r(3) - 1 loop
      lat_min := lat_min + 2;
      lat_max := lat_max + 2 + SHADE_NORM_CYCLES + 1 + 3;
      if r(4 + 8 * i) = 0 then  -- a point light's L is normalised
        lat_min := lat_min + SHADE_NORM_CYCLES;
        lat_max := lat_max + SHADE_NORM_CYCLES;
      end if;
    end loop;
    seen_min := integer'high;
    seen_max := 0;

    while not endfile(f) loop
      next_line(f, l, lineno, ok);
      for a in 0 to 2 loop
        read_col(l, a = 0, "grad_" & AXIS(a + 1), lineno, i_grad(a), ok, errs);
      end loop;
      for a in 0 to 2 loop
        read_col(l, false, "tf_" & CH(a + 1), lineno, i_tf(a), ok, errs);
      end loop;
      for a in 0 to 2 loop
        read_col(l, false, "gpos_" & AXIS(a + 1), lineno, i_gpos(a), ok, errs);
      end loop;
      for a in 0 to 2 loop
        read_col(l, false, "dir_" & AXIS(a + 1), lineno, i_dir(a), ok, errs);
      end loop;
      for a in 0 to 2 loop
        read_col(l, false, "rgb_" & CH(a + 1), lineno, e_rgb(a), ok, errs);
      end loop;
      read_col(l, false, "sat", lineno, e_sat, ok, errs);
      end_of_line(l, lineno, ok, errs);
      next when not ok;

      grad <= i_grad;
      tf <= i_tf;
      gpos <= i_gpos;
      dir <= i_dir;
      in_valid <= '1';
      wait for HALF;
      check(lineno, "in_ready", "1", (0 => in_ready), errs);
      edge(clk);
      in_valid <= '0';
      await_out(clk, out_valid, lat_max + 1, lat);
      if out_valid /= '1' then
        report "line " & integer'image(lineno) & ": no out_valid within " &
          integer'image(lat) & " cycles" severity error;
        finish_run(TB, lineno, errs + 1);
      end if;
      for a in 0 to 2 loop
        check(lineno, "rgb_" & CH(a + 1), e_rgb(a), rgb(a), errs);
      end loop;
      check(lineno, "sat", e_sat, sat, errs);
      m2 := (others => '0');
      for a in 0 to 2 loop
        m2 := m2 + signed(i_grad(a)) * signed(i_grad(a));
      end loop;
      if m2 = 0 then
        check(lineno, "latency (cycles)", std_logic_vector(to_unsigned(SHADE_FLAT_CYCLES, 16)),
              std_logic_vector(to_unsigned(lat, 16)), errs);
      elsif lat < lat_min or lat > lat_max then
        check(lineno, "latency (cycles) within " & integer'image(lat_min) & ".." &
              integer'image(lat_max), std_logic_vector(to_unsigned(lat_min, 16)),
              std_logic_vector(to_unsigned(lat, 16)), errs);
      else
        seen_min := minimum(seen_min, lat);
        seen_max := maximum(seen_max, lat);
      end if;
      edge(clk);
    end loop;
    if seen_max > 0 then
      report TB & ": latency " & integer'image(seen_min) & " to " & integer'image(seen_max) &
        " cycles (bounds " & integer'image(lat_min) & " to " & integer'image(lat_max) & ")" severity note;
    end if;
    finish_run(TB, lineno, errs);
    wait;
  end process run;
end architecture sim;
