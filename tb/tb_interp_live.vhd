-- tb_interp_live: interp (fpga/rtl/interp.vhd) against the C model running beside it
-- (c5ref_interp, the model's c5_interp_blend; docs/vectors.md, "The model inside the
-- simulator").
--
-- Drives:  one transaction a cycle from SEED alone, SAMPLES of them: weights 0, 2^-15, 1/2,
--          1 - 2^-15 or random; corners 0, 255 or random.
-- Checks:  LAT cycles later, out_valid = 1 and value = the model's; the first difference
--          ends the run: "FAIL tb_interp_live: seed S sample N: value: model X, VHDL Y".
-- Latency: LAT = INTERP_LATENCY (dp_pkg).
-- Usage:   ghdl -r --std=08 tb_interp_live -gSEED=1 -gSAMPLES=5000 (./libc5ref.so beside)
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.c5ref_pkg.all;
use work.tb_pkg.all;

entity tb_interp_live is
  generic (SEED : positive := 1; SAMPLES : positive := 5000);
end entity tb_interp_live;

architecture sim of tb_interp_live is
  constant TB  : string := "tb_interp_live";
  constant AT  : string := live_at(TB, SEED, "sample");
  constant LAT : positive := INTERP_LATENCY;
  signal clk, rst, in_valid, out_valid : std_logic := '0';
  signal frac : frac3_t := (others => (others => '0'));
  signal v : voxel8_t := (others => (others => '0'));
  signal value : std_logic_vector(SIG_SAMPLE_VALUE_WIDTH - 1 downto 0);
  signal due : integer;  -- the model's value for the sample driven LAT cycles before
begin
  dut : entity work.interp
    port map (clk => clk, rst => rst, in_valid => in_valid, frac => frac, v => v,
              out_valid => out_valid, value => value);

  run : process
    constant FMAX : integer := 2 ** SIG_VOXEL_FRAC_WIDTH - 1;
    variable rnd : random_t;
    variable fi : integer_vector(0 to 2);
    variable vi : integer_vector(0 to 7);
  begin
    rnd.seed(SEED);
    reset(clk, rst);
    for n in 0 to SAMPLES + LAT - 1 loop
      if n < SAMPLES then
        for a in 0 to 2 loop
          case rnd.pick(5) is
            when 0 => fi(a) := 0;
            when 1 => fi(a) := 1;
            when 2 => fi(a) := (FMAX + 1) / 2;
            when 3 => fi(a) := FMAX;
            when others => fi(a) := rnd.pick(FMAX + 1);
          end case;
          frac(a) <= std_logic_vector(to_unsigned(fi(a), SIG_VOXEL_FRAC_WIDTH));
        end loop;
        for k in 0 to 7 loop
          case rnd.pick(4) is
            when 0 => vi(k) := 0;
            when 1 => vi(k) := 255;
            when others => vi(k) := rnd.pick(256);
          end case;
          v(k) <= std_logic_vector(to_unsigned(vi(k), 8));
        end loop;
        due <= transport c5ref_interp(fi(0), fi(1), fi(2), vi(0), vi(1), vi(2), vi(3), vi(4), vi(5), vi(6),
                                      vi(7)) after LAT * PERIOD;
      end if;
      in_valid <= '1' when n < SAMPLES else '0';
      wait for HALF;  -- clock low: this cycle's outputs are stable
      if n >= LAT then
        live_expect(AT, n - LAT, "out_valid", 1, live_bit(out_valid));
        live_expect(AT, n - LAT, "value", due, to_integer(unsigned(value)));
      end if;
      edge(clk);
    end loop;
    live_pass(TB, SEED, integer'image(SAMPLES) & " samples");
  end process run;
end architecture sim;
