-- tb_composite_live: composite (fpga/rtl/composite.vhd) against the C model running beside it
-- (c5ref_cp_*, the model's c5_composite; docs/vectors.md, "The model inside the simulator").
--
-- Drives:  one sample a cycle from SEED alone, SAMPLES of them: contribution, ray opacity
--          below max_opacity, colours, alpha and shaded colours at 0, their maximum or
--          random, max_opacity at 1, 0.95 or random, one shadow ray in ten.
-- Checks:  LAT cycles later, out_valid = 1 and rgb_out opa_out done sat = the model's; the
--          first difference ends the run: "FAIL tb_composite_live: seed S sample N: PORT:
--          model X, VHDL Y".
-- Latency: LAT = COMPOSITE_LATENCY (dp_pkg).
-- Usage:   ghdl -r --std=08 tb_composite_live -gSEED=1 -gSAMPLES=5000 (./libc5ref.so beside)
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.c5ref_pkg.all;
use work.tb_pkg.all;

entity tb_composite_live is
  generic (SEED : positive := 1; SAMPLES : positive := 5000);
end entity tb_composite_live;

architecture sim of tb_composite_live is
  constant TB  : string := "tb_composite_live";
  constant AT  : string := live_at(TB, SEED, "sample");
  constant LAT : positive := COMPOSITE_LATENCY;
  signal clk, rst, in_valid, out_valid, shadow, done : std_logic := '0';
  signal w : std_logic_vector(RAY_PACKET_CONTRIBUTION_WIDTH - 1 downto 0) := (others => '0');
  signal opa, a_max, opa_out : std_logic_vector(SIG_MAX_OPACITY_WIDTH - 1 downto 0) := (others => '0');
  signal alpha : std_logic_vector(SIG_TF_RGBA_WIDTH - 1 downto 0) := (others => '0');
  signal rgb, rgb_out : rgb3_t := (others => (others => '0'));
  signal c : shaded3_t := (others => (others => '0'));
  signal sat : std_logic_vector(1 downto 0);
  -- the model's rgb_out x3, opa_out, done, sat, LAT cycles after their sample
  signal due : integer_vector(0 to 5);
begin
  dut : entity work.composite
    port map (clk => clk, rst => rst, in_valid => in_valid, w => w, opa => opa, rgb => rgb, alpha => alpha,
              c => c, shadow => shadow, a_max => a_max, out_valid => out_valid, rgb_out => rgb_out,
              opa_out => opa_out, done => done, sat => sat);

  run : process
    constant ONE : integer := 2 ** SIG_MAX_OPACITY_FRAC;
    constant RGB_MAX : integer := 2 ** SIG_SAMPLE_RGB_WIDTH - 1;
    constant C_MAX : integer := 2 ** SIG_SHADED_RGB_WIDTH - 1;
    variable rnd : random_t;
    variable x : integer_vector(0 to 10);  -- w, opa, rgb x3, alpha, c x3, shadow, a_max
    variable e : integer_vector(0 to 5);
    variable rc : integer;

    -- 0, the maximum or a value below it
    impure function edge_or_any(max : natural) return natural is
    begin
      case rnd.pick(4) is
        when 0 => return 0;
        when 1 => return max;
        when others => return rnd.pick(max + 1);
      end case;
    end function;
  begin
    rnd.seed(SEED);
    reset(clk, rst);
    for n in 0 to SAMPLES + LAT - 1 loop
      if n < SAMPLES then
        case rnd.pick(3) is
          when 0 => x(10) := ONE;
          when 1 => x(10) := 31130;  -- 0.95
          when others => x(10) := 1 + rnd.pick(ONE);
        end case;
        x(0) := edge_or_any(ONE);
        x(1) := rnd.pick(x(10));        -- a ray still compositing: below max_opacity
        for k in 2 to 4 loop
          x(k) := edge_or_any(RGB_MAX);
        end loop;
        x(5) := edge_or_any(ONE);
        for k in 6 to 8 loop
          x(k) := edge_or_any(C_MAX);
        end loop;
        x(9) := 0;
        if rnd.pick(10) = 0 then
          x(9) := 1;
        end if;
        for k in 0 to 10 loop
          rc := c5ref_cp_set(k, x(k));
        end loop;
        rc := c5ref_cp_run;
        for k in 0 to 5 loop
          e(k) := c5ref_cp_out(k);
        end loop;
        due <= transport e after LAT * PERIOD;
        w <= std_logic_vector(to_unsigned(x(0), w'length));
        opa <= std_logic_vector(to_unsigned(x(1), opa'length));
        for k in 0 to 2 loop
          rgb(k) <= std_logic_vector(to_unsigned(x(2 + k), SIG_SAMPLE_RGB_WIDTH));
          c(k) <= std_logic_vector(to_unsigned(x(6 + k), SIG_SHADED_RGB_WIDTH));
        end loop;
        alpha <= std_logic_vector(to_unsigned(x(5), alpha'length));
        shadow <= '1' when x(9) = 1 else '0';
        a_max <= std_logic_vector(to_unsigned(x(10), a_max'length));
      end if;
      in_valid <= '1' when n < SAMPLES else '0';
      wait for HALF;  -- clock low: this cycle's outputs are stable
      if n >= LAT then
        live_expect(AT, n - LAT, "out_valid", 1, live_bit(out_valid));
        for k in 0 to 2 loop
          live_expect(AT, n - LAT, "rgb_out(" & integer'image(k) & ")", due(k), to_integer(unsigned(rgb_out(k))));
        end loop;
        live_expect(AT, n - LAT, "opa_out", due(3), to_integer(unsigned(opa_out)));
        live_expect(AT, n - LAT, "done", due(4), live_bit(done));
        live_expect(AT, n - LAT, "sat", due(5), to_integer(unsigned(sat)));
      end if;
      edge(clk);
    end loop;
    live_pass(TB, SEED, integer'image(SAMPLES) & " samples");
  end process run;
end architecture sim;
