-- tb_gradient_live: gradient (fpga/rtl/gradient.vhd) against the C model running beside it
-- (c5ref_gr_*, the model's c5_grad_blend; docs/vectors.md, "The model inside the
-- simulator").
--
-- Drives:  one transaction a cycle from SEED alone, SAMPLES of them: weights 0, 2^-15, 1/2,
--          1 - 2^-15 or random; central differences -255, 0, +255 or random; gs 0, 1 or
--          random.
-- Checks:  LAT cycles later, out_valid = 1 and grad = the model's; the first difference ends
--          the run: "FAIL tb_gradient_live: seed S sample N: grad(A): model X, VHDL Y".
-- Latency: LAT = GRADIENT_LATENCY (dp_pkg).
-- Usage:   ghdl -r --std=08 tb_gradient_live -gSEED=1 -gSAMPLES=5000 (./libc5ref.so beside)
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.c5ref_pkg.all;
use work.tb_pkg.all;

entity tb_gradient_live is
  generic (SEED : positive := 1; SAMPLES : positive := 5000);
end entity tb_gradient_live;

architecture sim of tb_gradient_live is
  constant TB  : string := "tb_gradient_live";
  constant AT  : string := live_at(TB, SEED, "sample");
  constant LAT : positive := GRADIENT_LATENCY;
  signal clk, rst, in_valid, out_valid : std_logic := '0';
  signal frac : frac3_t := (others => (others => '0'));
  signal d : diff24_t := (others => (others => (others => '0')));
  signal gs : gscale3_t := (others => (others => '0'));
  signal grad : grad3_t;
  signal due : integer_vector(0 to 2);  -- the model's gradient, LAT cycles after its sample
begin
  dut : entity work.gradient
    port map (clk => clk, rst => rst, in_valid => in_valid, frac => frac, d => d, gs => gs,
              out_valid => out_valid, grad => grad);

  run : process
    constant FMAX : integer := 2 ** SIG_VOXEL_FRAC_WIDTH - 1;
    constant GS_ONE : integer := 2 ** (SIG_GRAD_SCALE_WIDTH - 1);
    variable rnd : random_t;
    variable x, rc : integer;
    variable e : integer_vector(0 to 2);
  begin
    rnd.seed(SEED);
    reset(clk, rst);
    for n in 0 to SAMPLES + LAT - 1 loop
      if n < SAMPLES then
        for a in 0 to 2 loop
          case rnd.pick(5) is
            when 0 => x := 0;
            when 1 => x := 1;
            when 2 => x := (FMAX + 1) / 2;
            when 3 => x := FMAX;
            when others => x := rnd.pick(FMAX + 1);
          end case;
          frac(a) <= std_logic_vector(to_unsigned(x, SIG_VOXEL_FRAC_WIDTH));
          rc := c5ref_gr_set(a, x);
          for k in 0 to 7 loop
            case rnd.pick(4) is
              when 0 => x := -255;
              when 1 => x := 255;
              when 2 => x := 0;
              when others => x := rnd.pick(511) - 255;
            end case;
            d(a)(k) <= std_logic_vector(to_signed(x, DIFF_BITS));
            rc := c5ref_gr_set(3 + 8 * a + k, x);
          end loop;
          case rnd.pick(3) is
            when 0 => x := 0;
            when 1 => x := GS_ONE;
            when others => x := rnd.pick(GS_ONE + 1);
          end case;
          gs(a) <= std_logic_vector(to_unsigned(x, SIG_GRAD_SCALE_WIDTH));
          rc := c5ref_gr_set(27 + a, x);
        end loop;
        for a in 0 to 2 loop
          e(a) := c5ref_gr_run(a);
        end loop;
        due <= transport e after LAT * PERIOD;
      end if;
      in_valid <= '1' when n < SAMPLES else '0';
      wait for HALF;  -- clock low: this cycle's outputs are stable
      if n >= LAT then
        live_expect(AT, n - LAT, "out_valid", 1, live_bit(out_valid));
        for a in 0 to 2 loop
          live_expect(AT, n - LAT, "grad(" & integer'image(a) & ")", due(a), to_integer(signed(grad(a))));
        end loop;
      end if;
      edge(clk);
    end loop;
    live_pass(TB, SEED, integer'image(SAMPLES) & " samples");
  end process run;
end architecture sim;
