-- Helpers shared by the ray queue's files (ray_queue.vhd, rq_stage.vhd, rq_addr_alloc.vhd):
-- the address width for a capacity, and the one comparison every stage makes.
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

package rq_pkg is
  -- Bits to number 0 .. n-1 (at least 1, so a 1-entry queue still has an address port).
  function clog2(n : positive) return positive;

  -- Does element a go before element b? The C model's goes_first (rtl_model/proc/ray_queue.c):
  -- an empty slot goes after everything; a smaller key goes first; on equal keys a fresh a
  -- (inserted, never settled) loses and any other a wins, which keeps equal keys FIFO.
  function goes_first(a_valid, a_fresh : std_logic; a_key : std_logic_vector;
                      b_valid : std_logic; b_key : std_logic_vector) return boolean;
end package rq_pkg;

package body rq_pkg is
  function clog2(n : positive) return positive is
    variable bits : positive := 1;
  begin
    while 2 ** bits < n loop
      bits := bits + 1;
    end loop;
    return bits;
  end function clog2;

  function goes_first(a_valid, a_fresh : std_logic; a_key : std_logic_vector;
                      b_valid : std_logic; b_key : std_logic_vector) return boolean is
  begin
    if a_valid /= '1' then
      return false;
    elsif b_valid /= '1' then
      return true;
    end if;
    -- key < key' or (key = key' and not fresh), as one comparator one bit wider:
    -- (a_key & fresh) < (b_key & 1) is true for a smaller key, and for an equal key
    -- exactly when fresh = 0. One carry chain instead of a less-than plus an equality.
    return unsigned(a_key & a_fresh) < unsigned(b_key & '1');
  end function goes_first;
end package body rq_pkg;
