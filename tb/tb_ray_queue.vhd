-- tb_ray_queue: ray_queue (fpga/rtl/ray_queue.vhd) against the golden vectors
-- ray_queue.*.hex, one line a clock cycle from the synchronous reset on.
--
-- Drives:  each cycle while the clock is low: insert_valid(1) insert_key(KEY_BITS)
--          insert_payload(PAYLOAD_BITS) pop_ready(1).
-- Checks:  in the same cycle, once the inputs have settled (the outputs depend on the
--          registers and this cycle's inputs): pop_valid(1) pop_key(KEY_BITS)
--          pop_payload(PAYLOAD_BITS) insert_accepted(1) full(1) count(clog2(CAPACITY + 1))
--          empty(1). A malformed line ends the run (every later cycle depends on it).
-- Latency: none (outputs of the cycle); the generics must match the file's configuration
--          (manifest.json), the board's is the default.
-- Usage:   ghdl -r --std=08 tb_ray_queue -gVECTORS=path/ray_queue.x.hex
library ieee;
use ieee.std_logic_1164.all;
use std.textio.all;
use work.rq_pkg.all;
use work.tb_pkg.all;
use work.vec_io_pkg.all;

entity tb_ray_queue is
  generic (
    VECTORS      : string := "ray_queue.hex";
    CAPACITY     : positive := 256;
    KEY_BITS     : positive := 32;
    PAYLOAD_BITS : positive := 32);
end entity tb_ray_queue;

architecture sim of tb_ray_queue is
  constant TB : string := "tb_ray_queue";

  signal clk, rst        : std_logic := '0';
  signal insert_valid    : std_logic := '0';
  signal insert_key      : std_logic_vector(KEY_BITS - 1 downto 0) := (others => '0');
  signal insert_payload  : std_logic_vector(PAYLOAD_BITS - 1 downto 0) := (others => '0');
  signal pop_ready       : std_logic := '0';
  signal pop_valid       : std_logic;
  signal pop_key         : std_logic_vector(KEY_BITS - 1 downto 0);
  signal pop_payload     : std_logic_vector(PAYLOAD_BITS - 1 downto 0);
  signal insert_accepted : std_logic;
  signal full            : std_logic;
  signal count           : std_logic_vector(clog2(CAPACITY + 1) - 1 downto 0);
  signal empty           : std_logic;
begin
  dut : entity work.ray_queue
    generic map (CAPACITY => CAPACITY, KEY_BITS => KEY_BITS, PAYLOAD_BITS => PAYLOAD_BITS)
    port map (
      clk => clk, rst => rst,
      insert_valid => insert_valid, insert_key => insert_key,
      insert_payload => insert_payload, pop_ready => pop_ready,
      pop_valid => pop_valid, pop_key => pop_key, pop_payload => pop_payload,
      insert_accepted => insert_accepted, full => full, count => count, empty => empty);

  run : process
    file f : text;
    variable l : line;
    variable lineno, errs : natural := 0;
    variable ok : boolean;     -- the line is well formed
    -- one line: inputs, then the expected outputs
    variable i_valid, i_ready, e_valid, e_acc, e_full, e_empty : std_logic_vector(0 downto 0);
    variable i_key, e_key : std_logic_vector(KEY_BITS - 1 downto 0);
    variable i_pay, e_pay : std_logic_vector(PAYLOAD_BITS - 1 downto 0);
    variable e_count : std_logic_vector(count'range);
  begin
    open_vectors(f, VECTORS, TB);
    reset(clk, rst);
    while not endfile(f) loop
      next_line(f, l, lineno, ok);
      read_col(l, true,  "insert_valid", lineno, i_valid, ok, errs);
      read_col(l, false, "insert_key", lineno, i_key, ok, errs);
      read_col(l, false, "insert_payload", lineno, i_pay, ok, errs);
      read_col(l, false, "pop_ready", lineno, i_ready, ok, errs);
      read_col(l, false, "pop_valid", lineno, e_valid, ok, errs);
      read_col(l, false, "pop_key", lineno, e_key, ok, errs);
      read_col(l, false, "pop_payload", lineno, e_pay, ok, errs);
      read_col(l, false, "insert_accepted", lineno, e_acc, ok, errs);
      read_col(l, false, "full", lineno, e_full, ok, errs);
      read_col(l, false, "count", lineno, e_count, ok, errs);
      read_col(l, false, "empty", lineno, e_empty, ok, errs);
      end_of_line(l, lineno, ok, errs);
      -- A malformed line has no inputs to apply, and every later cycle depends on this
      -- one: the run ends here (FAIL).
      exit when not ok;

      insert_valid   <= i_valid(0);
      insert_key     <= i_key;
      insert_payload <= i_pay;
      pop_ready      <= i_ready(0);
      wait for HALF;  -- clock low: the outputs of this cycle settle

      check(lineno, "pop_valid", e_valid, (0 => pop_valid), errs);
      check(lineno, "pop_key", e_key, pop_key, errs);
      check(lineno, "pop_payload", e_pay, pop_payload, errs);
      check(lineno, "insert_accepted", e_acc, (0 => insert_accepted), errs);
      check(lineno, "full", e_full, (0 => full), errs);
      check(lineno, "count", e_count, count, errs);
      check(lineno, "empty", e_empty, (0 => empty), errs);

      edge(clk);
    end loop;
    finish_run(TB, lineno, errs);
    wait;
  end process run;
end architecture sim;
