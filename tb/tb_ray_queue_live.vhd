-- tb_ray_queue_live: ray_queue (fpga/rtl/ray_queue.vhd) against the C model's sorter running
-- beside it (c5ref_rq_*; docs/vectors.md, "The model inside the simulator").
--
-- Drives:  CYCLES cycles of stimulus from SEED alone, in phases that fill the queue to full
--          and past it (refused inserts, pop + insert while full), drain it to empty (pops on
--          an empty queue) and mix, with keys drawn from a small range (equal keys in
--          flight), the extremes and the whole 32 bits.
-- Checks:  every output in the cycle it is produced; the first difference ends the run:
--          "FAIL tb_ray_queue_live: seed S cycle N: PORT: model X, VHDL Y"; otherwise
--          "PASS tb_ray_queue_live: seed S, N cycles, F full, R refused inserts".
-- Latency: none (outputs of the cycle).
-- Usage:   ghdl -r --std=08 tb_ray_queue_live -gSEED=1 -gCYCLES=5000 (./libc5ref.so beside)
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use work.rq_pkg.all;
use work.c5ref_pkg.all;
use work.tb_pkg.all;

entity tb_ray_queue_live is
  generic (SEED : positive := 1; CYCLES : positive := 5000; CAPACITY : positive := 256);
end entity tb_ray_queue_live;

architecture sim of tb_ray_queue_live is
  constant TB : string := "tb_ray_queue_live";
  constant AT : string := live_at(TB, SEED, "cycle");
  signal clk, rst : std_logic := '0';
  signal insert_valid, pop_ready : std_logic := '0';
  signal insert_key, insert_payload : std_logic_vector(31 downto 0) := (others => '0');
  signal pop_valid, insert_accepted, full, empty : std_logic;
  signal pop_key, pop_payload : std_logic_vector(31 downto 0);
  signal count : std_logic_vector(clog2(CAPACITY + 1) - 1 downto 0);
begin
  dut : entity work.ray_queue
    generic map (CAPACITY => CAPACITY, KEY_BITS => 32, PAYLOAD_BITS => 32)
    port map (
      clk => clk, rst => rst,
      insert_valid => insert_valid, insert_key => insert_key,
      insert_payload => insert_payload, pop_ready => pop_ready,
      pop_valid => pop_valid, pop_key => pop_key, pop_payload => pop_payload,
      insert_accepted => insert_accepted, full => full, count => count, empty => empty);

  run : process
    variable rnd : random_t;
    variable x : real;
    variable p_ins, p_pop : real;
    variable key : std_logic_vector(31 downto 0);
    variable ins, pop : std_logic;
    variable rc, nfull, nrefused : integer := 0;

    impure function half16 return std_logic_vector is
    begin
      return std_logic_vector(to_unsigned(rnd.pick(65536), 16));
    end function;
  begin
    rnd.seed(SEED);
    assert c5ref_rq_reset(CAPACITY, 32) = 0 report "the model refused the configuration" severity failure;
    reset(clk, rst);
    for cyc in 0 to CYCLES - 1 loop
      -- phases of 400 cycles: fill past full, drain past empty, mixed
      case (cyc / 400) mod 3 is
        when 0 => p_ins := 0.95; p_pop := 0.05;
        when 1 => p_ins := 0.15; p_pop := 0.95;
        when others => p_ins := 0.6; p_pop := 0.5;
      end case;
      ins := '0';
      pop := '0';
      if rnd.draw < p_ins then
        ins := '1';
      end if;
      if rnd.draw < p_pop then
        pop := '1';
      end if;
      x := rnd.draw;
      if x < 0.5 then     -- a small range: equal keys
        key := (31 downto 4 => '0') & half16(3 downto 0);
      elsif x < 0.6 then
        key := (others => '0');
      elsif x < 0.7 then
        key := (others => '1');
      else
        key := half16 & half16;
      end if;
      insert_valid <= ins;
      insert_key <= key;
      insert_payload <= std_logic_vector(to_unsigned(cyc, 32));
      pop_ready <= pop;
      wait for HALF;  -- clock low: the outputs of this cycle settle
      rc := c5ref_rq_step(live_bit(ins), to_integer(signed(key)), cyc, live_bit(pop));
      live_expect(AT, cyc, "pop_valid", c5ref_rq_out(0), live_bit(pop_valid));
      live_expect(AT, cyc, "pop_key", c5ref_rq_out(1), to_integer(signed(pop_key)));
      live_expect(AT, cyc, "pop_payload", c5ref_rq_out(2), to_integer(signed(pop_payload)));
      live_expect(AT, cyc, "insert_accepted", c5ref_rq_out(3), live_bit(insert_accepted));
      live_expect(AT, cyc, "full", c5ref_rq_out(4), live_bit(full));
      live_expect(AT, cyc, "count", c5ref_rq_out(5), to_integer(unsigned(count)));
      live_expect(AT, cyc, "empty", c5ref_rq_out(6), live_bit(empty));
      nfull := nfull + live_bit(full);
      nrefused := nrefused + live_bit(ins and full);
      edge(clk);
    end loop;
    live_pass(TB, SEED, integer'image(CYCLES) & " cycles, " & integer'image(nfull) & " full, " &
              integer'image(nrefused) & " refused inserts");
  end process run;
end architecture sim;
