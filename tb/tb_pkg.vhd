-- The clock, reset and handshake every testbench (tb/tb_*.vhd) drives, and the seeded
-- random source of the `_live` ones.
--
-- A cycle lasts PERIOD = 2 * HALF: the testbench changes the inputs while the clock is
-- low, waits HALF (the outputs settle), compares them, then `edge` raises the clock that
-- ends the cycle and lowers it again HALF later. Procedures that drive signals or wait are
-- called from the testbench's process, whose drivers they use.
library ieee;
use ieee.std_logic_1164.all;
use ieee.math_real.all;

package tb_pkg is
  constant HALF   : time := 5 ns;
  constant PERIOD : time := 2 * HALF;

  -- The rising edge that ends a cycle whose outputs were compared: clk = 1 for HALF, then 0.
  procedure edge(signal clk : out std_logic);

  -- A whole cycle with nothing to compare: HALF low, then `edge`.
  procedure tick(signal clk : out std_logic);

  -- The synchronous reset: one rising edge with rst = 1, then rst = 0.
  procedure reset(signal clk, rst : out std_logic);

  -- After the edge that took a transaction (in_valid = 1): the cycles until out_valid = 1,
  -- counted from 1, each cycle's outputs settled (HALF after the clock fell) before
  -- out_valid is looked at, and an `edge` after every cycle without it. Returns with the
  -- clock low and the outputs settled, in the cycle out_valid = 1 (compare, then `edge`) or,
  -- with out_valid still 0, in cycle lat = limit + 1 (the caller reports the timeout).
  procedure await_out(signal clk : out std_logic; signal out_valid : std_logic; limit : positive;
                      lat : out natural);

  -- The stimulus of a `_live` testbench: ieee.math_real.uniform on the seeds (SEED, 20261127),
  -- so that the stream comes from SEED alone.
  type random_t is protected
    procedure seed(s : positive);                      -- first, before any draw
    impure function draw return real;                  -- uniform in (0, 1)
    impure function pick(n : positive) return natural; -- uniform in 0 .. n - 1
  end protected random_t;
end package tb_pkg;

package body tb_pkg is
  procedure edge(signal clk : out std_logic) is
  begin
    clk <= '1';
    wait for HALF;
    clk <= '0';
  end procedure edge;

  procedure tick(signal clk : out std_logic) is
  begin
    wait for HALF;
    edge(clk);
  end procedure tick;

  procedure reset(signal clk, rst : out std_logic) is
  begin
    rst <= '1';
    tick(clk);
    rst <= '0';
  end procedure reset;

  procedure await_out(signal clk : out std_logic; signal out_valid : std_logic; limit : positive;
                      lat : out natural) is
    variable n : natural := 0;
  begin
    loop
      n := n + 1;
      wait for HALF;
      exit when out_valid = '1' or n > limit;
      edge(clk);
    end loop;
    lat := n;
  end procedure await_out;

  type random_t is protected body
    variable s1 : positive := 1;
    variable s2 : positive := 20261127;

    procedure seed(s : positive) is
    begin
      s1 := s;
      s2 := 20261127;
    end procedure seed;

    impure function draw return real is
      variable r : real;
    begin
      uniform(s1, s2, r);
      return r;
    end function draw;

    impure function pick(n : positive) return natural is
    begin
      return integer(floor(draw * real(n))) mod n;
    end function pick;
  end protected body random_t;
end package body tb_pkg;
