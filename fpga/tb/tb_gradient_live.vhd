-- The gradient blend against the C model running beside it (docs/vectors.md, "The model
-- inside the simulator"): one transaction a cycle from SEED alone (weights 0, 2^-15, 1/2,
-- 1 - 2^-15 or random; central differences -255, 0, +255 or random; gs 0, 1 or random) into
-- fpga/rtl/gradient.vhd and into the model's c5_grad_blend (c5ref_gr_*); the model's
-- gradient is held for GRADIENT_LATENCY cycles and compared with the DUT's then. The first
-- difference ends the run: "FAIL tb_gradient_live: seed S sample N: grad(A): model X, VHDL Y".
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use ieee.math_real.all;
use std.env.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.c5ref_pkg.all;

entity tb_gradient_live is
  generic (SEED : positive := 1; SAMPLES : positive := 5000);
end entity tb_gradient_live;

architecture sim of tb_gradient_live is
  constant HALF : time := 5 ns;
  constant LAT : positive := GRADIENT_LATENCY;
  signal clk, rst, in_valid, out_valid : std_logic := '0';
  signal frac : frac3_t := (others => (others => '0'));
  signal d : diff24_t := (others => (others => (others => '0')));
  signal gs : gscale3_t := (others => (others => '0'));
  signal grad : grad3_t;
begin
  dut : entity work.gradient
    port map (clk => clk, rst => rst, in_valid => in_valid, frac => frac, d => d, gs => gs,
              out_valid => out_valid, grad => grad);

  run : process
    variable s1 : positive := SEED;
    variable s2 : positive := 20261127;
    variable r : real;
    variable x, rc : integer;
    type g3_t is array (0 to 2) of integer;
    type ring_t is array (0 to LAT) of g3_t;
    variable ring : ring_t;
    variable e : g3_t;
    constant FMAX : integer := 2 ** SIG_VOXEL_FRAC_WIDTH - 1;
    constant GS_ONE : integer := 2 ** (SIG_GRAD_SCALE_WIDTH - 1);

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
            when 0 => x := 0;
            when 1 => x := 1;
            when 2 => x := (FMAX + 1) / 2;
            when 3 => x := FMAX;
            when others => x := pick(FMAX + 1);
          end case;
          frac(a) <= std_logic_vector(to_unsigned(x, SIG_VOXEL_FRAC_WIDTH));
          rc := c5ref_gr_set(a, x);
          for k in 0 to 7 loop
            case pick(4) is
              when 0 => x := -255;
              when 1 => x := 255;
              when 2 => x := 0;
              when others => x := pick(511) - 255;
            end case;
            d(a)(k) <= std_logic_vector(to_signed(x, DIFF_BITS));
            rc := c5ref_gr_set(3 + 8 * a + k, x);
          end loop;
          case pick(3) is
            when 0 => x := 0;
            when 1 => x := GS_ONE;
            when others => x := pick(GS_ONE + 1);
          end case;
          gs(a) <= std_logic_vector(to_unsigned(x, SIG_GRAD_SCALE_WIDTH));
          rc := c5ref_gr_set(27 + a, x);
        end loop;
        for a in 0 to 2 loop
          e(a) := c5ref_gr_run(a);
        end loop;
        ring(n mod (LAT + 1)) := e;
        in_valid <= '1';
      else
        in_valid <= '0';
      end if;
      wait for HALF;  -- clock low: this cycle's outputs are stable
      if n >= LAT then
        e := ring((n - LAT) mod (LAT + 1));
        live_expect("tb_gradient_live", SEED, "sample", n - LAT, "out_valid", 1, live_bit(out_valid));
        for a in 0 to 2 loop
          live_expect("tb_gradient_live", SEED, "sample", n - LAT, "grad(" & integer'image(a) & ")", e(a),
                      to_integer(signed(grad(a))));
        end loop;
      end if;
      clk <= '1';
      wait for HALF;
      clk <= '0';
    end loop;
    report "PASS tb_gradient_live: seed " & integer'image(SEED) & ", " & integer'image(SAMPLES) & " samples"
      severity note;
    finish(0);
  end process run;
end architecture sim;
