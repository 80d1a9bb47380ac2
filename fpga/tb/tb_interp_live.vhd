-- Trilinear interpolation against the C model running beside it (docs/vectors.md, "The
-- model inside the simulator"): one transaction a cycle from SEED alone (weights 0, 2^-15,
-- 1/2, 1 - 2^-15 or random; corners 0, 255 or random) into fpga/rtl/interp.vhd and into the
-- model's c5_interp_blend (c5ref_interp); the model's value is held for INTERP_LATENCY
-- cycles and compared with the DUT's output then. The first difference ends the run:
-- "FAIL tb_interp_live: seed S sample N: value: model X, VHDL Y" (exit status 1).
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use ieee.math_real.all;
use std.env.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.c5ref_pkg.all;

entity tb_interp_live is
  generic (SEED : positive := 1; SAMPLES : positive := 5000);
end entity tb_interp_live;

architecture sim of tb_interp_live is
  constant HALF : time := 5 ns;
  constant LAT : positive := INTERP_LATENCY;
  signal clk, rst, in_valid, out_valid : std_logic := '0';
  signal frac : frac3_t := (others => (others => '0'));
  signal v : voxel8_t := (others => (others => '0'));
  signal value : std_logic_vector(SIG_SAMPLE_VALUE_WIDTH - 1 downto 0);
begin
  dut : entity work.interp
    port map (clk => clk, rst => rst, in_valid => in_valid, frac => frac, v => v,
              out_valid => out_valid, value => value);

  run : process
    variable s1 : positive := SEED;
    variable s2 : positive := 20261127;
    variable r : real;
    variable fi : integer_vector(0 to 2);
    variable vi : integer_vector(0 to 7);
    type ring_t is array (0 to LAT) of integer;
    variable ring : ring_t;
    constant FMAX : integer := 2 ** SIG_VOXEL_FRAC_WIDTH - 1;

    impure function pick(n : positive) return natural is
    begin
      uniform(s1, s2, r);
      return integer(floor(r * real(n))) mod n;
    end function;
  begin
    rst <= '1';
    wait for HALF;
    clk <= '1';
    wait for HALF;
    clk <= '0';
    rst <= '0';
    for n in 0 to SAMPLES + LAT - 1 loop
      if n < SAMPLES then
        for a in 0 to 2 loop
          case pick(5) is
            when 0 => fi(a) := 0;
            when 1 => fi(a) := 1;
            when 2 => fi(a) := (FMAX + 1) / 2;
            when 3 => fi(a) := FMAX;
            when others => fi(a) := pick(FMAX + 1);
          end case;
          frac(a) <= std_logic_vector(to_unsigned(fi(a), SIG_VOXEL_FRAC_WIDTH));
        end loop;
        for k in 0 to 7 loop
          case pick(4) is
            when 0 => vi(k) := 0;
            when 1 => vi(k) := 255;
            when others => vi(k) := pick(256);
          end case;
          v(k) <= std_logic_vector(to_unsigned(vi(k), 8));
        end loop;
        ring(n mod (LAT + 1)) := c5ref_interp(fi(0), fi(1), fi(2), vi(0), vi(1), vi(2), vi(3), vi(4), vi(5),
                                              vi(6), vi(7));
        in_valid <= '1';
      else
        in_valid <= '0';
      end if;
      wait for HALF;  -- clock low: this cycle's outputs are stable
      if n >= LAT then
        live_expect("tb_interp_live", SEED, "sample", n - LAT, "out_valid", 1, live_bit(out_valid));
        live_expect("tb_interp_live", SEED, "sample", n - LAT, "value", ring((n - LAT) mod (LAT + 1)),
                    to_integer(unsigned(value)));
      end if;
      clk <= '1';
      wait for HALF;
      clk <= '0';
    end loop;
    report "PASS tb_interp_live: seed " & integer'image(SEED) & ", " & integer'image(SAMPLES) & " samples"
      severity note;
    finish(0);
  end process run;
end architecture sim;
