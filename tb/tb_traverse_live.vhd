-- tb_traverse_live: traverse (fpga/rtl/traverse.vhd) against the C model running beside it
-- (c5ref_tr_*, the model's c5_trav_step; docs/vectors.md, "The model inside the simulator").
--
-- Drives:  one step a cycle from SEED alone, STEPS of them: grids of 1 to GRID_MAX voxels an
--          axis (half of them up to 511), a cell box inside, positions in the cell or up to two voxels around it (one
--          in ten anywhere within 8 voxels of the grid), step vectors up to 8 voxels a
--          component (a quarter of them below 2^-8), lifetimes 0, short, unbounded (4095) or
--          any, block_empty drawn inside the grid.
-- Checks:  LAT cycles later, out_valid = 1 and action leaped pos_out lifetime_out = the
--          model's; the first difference ends the run: "FAIL tb_traverse_live: seed S step N:
--          PORT: model X, VHDL Y".
-- Latency: LAT = TRAVERSE_LATENCY (dp_pkg).
-- Usage:   ghdl -r --std=08 tb_traverse_live -gSEED=1 -gSTEPS=5000 (./libc5ref.so beside)
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.c5ref_pkg.all;
use work.tb_pkg.all;

entity tb_traverse_live is
  generic (SEED : positive := 1; STEPS : positive := 5000);
end entity tb_traverse_live;

architecture sim of tb_traverse_live is
  constant TB  : string := "tb_traverse_live";
  constant AT  : string := live_at(TB, SEED, "step");
  constant LAT : positive := TRAVERSE_LATENCY;
  signal clk, rst, in_valid, out_valid, block_empty : std_logic := '0';
  signal pos, pos_out : pos3_t := (others => (others => '0'));
  signal step : step3_t := (others => (others => '0'));
  signal lifetime, lifetime_out : std_logic_vector(RAY_PACKET_LIFETIME_WIDTH - 1 downto 0) := (others => '0');
  signal cell_lo, cell_hi, dims : grid3_t := (others => (others => '0'));
  signal action : std_logic_vector(1 downto 0);
  signal leaped : std_logic_vector(LEAPED_BITS - 1 downto 0);
  -- the model's action, leaped, pos_out x3, lifetime_out, LAT cycles after their step
  signal due : integer_vector(0 to 5);
begin
  dut : entity work.traverse
    port map (clk => clk, rst => rst, in_valid => in_valid, pos => pos, step => step, lifetime => lifetime,
              cell_lo => cell_lo, cell_hi => cell_hi, dims => dims, block_empty => block_empty,
              out_valid => out_valid, action => action, leaped => leaped, pos_out => pos_out,
              lifetime_out => lifetime_out);

  run : process
    constant ONE : integer := 2 ** POS_FRAC;
    -- The model's largest grid (C5_MODEL_MAX_GRID, rtl_model/model_limits.h): the grid_pos
    -- format holds its positions and the 8 voxels around it, not those of a 13-bit grid.
    constant GRID_MAX : positive := 8000;
    constant SMAX : integer := 2 ** (SIG_STEP_VEC_WIDTH - 1);
    variable rnd : random_t;
    variable dm, lo, hi, x, y, q, life, rc : integer;
    variable sv : integer_vector(0 to 2);
    variable in_grid : boolean;
    variable e : integer_vector(0 to 5);

    impure function between(a, b : integer) return integer is  -- a <= x < b
    begin
      return a + rnd.pick(b - a);
    end function;
  begin
    rnd.seed(SEED);
    reset(clk, rst);
    for n in 0 to STEPS + LAT - 1 loop
      if n < STEPS then
        in_grid := true;
        for a in 0 to 2 loop
          if n mod 2 = 0 then
            dm := 1 + rnd.pick(GRID_MAX);
          else
            dm := 1 + rnd.pick(511);
          end if;
          x := rnd.pick(dm);
          y := rnd.pick(dm);
          lo := minimum(x, y);
          hi := maximum(x, y) + 1;
          if n mod 10 = 9 then
            q := between(-8 * ONE, (dm + 8) * ONE);
          else
            q := between((lo - 2) * ONE, (hi + 2) * ONE);
          end if;
          in_grid := in_grid and q >= 0 and q < dm * ONE;
          dims(a) <= std_logic_vector(to_unsigned(dm, GRID_BITS));
          cell_lo(a) <= std_logic_vector(to_unsigned(lo, GRID_BITS));
          cell_hi(a) <= std_logic_vector(to_unsigned(hi, GRID_BITS));
          pos(a) <= std_logic_vector(to_signed(q, POS_BITS));
          rc := c5ref_tr_set(a, q);
          rc := c5ref_tr_set(7 + a, lo);
          rc := c5ref_tr_set(10 + a, hi);
          rc := c5ref_tr_set(13 + a, dm);
          if n mod 4 = 0 then
            sv(a) := between(-256, 256);                -- tiny steps
          else
            sv(a) := between(-SMAX, SMAX);
          end if;
        end loop;
        if sv(0) = 0 and sv(1) = 0 and sv(2) = 0 then
          sv(0) := 1;
        end if;
        for a in 0 to 2 loop
          step(a) <= std_logic_vector(to_signed(sv(a), SIG_STEP_VEC_WIDTH));
          rc := c5ref_tr_set(3 + a, sv(a));
        end loop;
        case rnd.pick(8) is
          when 0 => life := 0;
          when 1 | 2 => life := rnd.pick(16);
          when 3 | 4 => life := LIFE_NONE;
          when others => life := rnd.pick(LIFE_NONE);
        end case;
        lifetime <= std_logic_vector(to_unsigned(life, lifetime'length));
        rc := c5ref_tr_set(6, life);
        x := 0;
        if in_grid and rnd.pick(2) = 1 then
          x := 1;
        end if;
        block_empty <= '1' when x = 1 else '0';
        rc := c5ref_tr_set(16, x);
        rc := c5ref_tr_run;
        for k in 0 to 5 loop
          e(k) := c5ref_tr_out(k);
        end loop;
        due <= transport e after LAT * PERIOD;
      end if;
      in_valid <= '1' when n < STEPS else '0';
      wait for HALF;  -- clock low: this cycle's outputs are stable
      if n >= LAT then
        live_expect(AT, n - LAT, "out_valid", 1, live_bit(out_valid));
        live_expect(AT, n - LAT, "action", due(0), to_integer(unsigned(action)));
        live_expect(AT, n - LAT, "leaped", due(1), to_integer(unsigned(leaped)));
        for a in 0 to 2 loop
          live_expect(AT, n - LAT, "pos_out(" & integer'image(a) & ")", due(2 + a), to_integer(signed(pos_out(a))));
        end loop;
        live_expect(AT, n - LAT, "lifetime_out", due(5), to_integer(unsigned(lifetime_out)));
      end if;
      edge(clk);
    end loop;
    live_pass(TB, SEED, integer'image(STEPS) & " steps");
  end process run;
end architecture sim;
