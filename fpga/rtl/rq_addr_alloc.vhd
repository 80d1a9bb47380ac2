-- The free-address allocator of the ray queue's payload RAM (the eDRAM): which of its
-- CAPACITY slots a newly inserted ray is written to. A pop frees its slot.
--
-- Addresses never used since reset come from a counter (`fresh`), returned ones from a
-- LIFO (`stack`): no initialisation pass over a free list after reset, and the LIFO lives
-- in a block RAM (CAPACITY x ADDR_BITS) instead of CAPACITY flip-flop words.
-- An alloc in the same cycle as a free takes the freed address directly and leaves both
-- unchanged: this is how a full queue that pops accepts that cycle's insert.
--
-- The LIFO's top must be readable combinationally (alloc_addr is used in the same cycle)
-- though the RAM reads synchronously, so the top is prefetched: after a push the top is
-- the pushed address (kept in `pushed`), after a pop the RAM reads the entry below into
-- its output register at the same edge. `top_is_pushed` says which of the two it is.
-- The caller never allocates more than CAPACITY addresses at once (full), and never frees
-- an address it does not hold; then stack depth + fresh count never exceed CAPACITY.
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

entity rq_addr_alloc is
  generic (
    CAPACITY   : positive;
    ADDR_BITS  : positive;   -- clog2(CAPACITY)
    COUNT_BITS : positive);  -- holds 0 .. CAPACITY
  port (
    clk, rst   : in  std_logic;  -- rst: synchronous; every address free again
    alloc      : in  std_logic;  -- take alloc_addr at this edge
    free       : in  std_logic;  -- return free_addr at this edge
    free_addr  : in  std_logic_vector(ADDR_BITS - 1 downto 0);
    alloc_addr : out std_logic_vector(ADDR_BITS - 1 downto 0));  -- valid when alloc = 1
end entity rq_addr_alloc;

architecture rtl of rq_addr_alloc is
  signal fresh         : unsigned(COUNT_BITS - 1 downto 0) := (others => '0');  -- next never-used
  signal depth         : unsigned(COUNT_BITS - 1 downto 0) := (others => '0');  -- LIFO entries
  signal pushed        : std_logic_vector(ADDR_BITS - 1 downto 0) := (others => '0');
  signal top_is_pushed : std_logic := '0';
  signal below         : std_logic_vector(ADDR_BITS - 1 downto 0);  -- RAM read: the entry below
  signal top           : std_logic_vector(ADDR_BITS - 1 downto 0);
  signal push, take    : std_logic;  -- free alone / alloc from the LIFO alone
  signal read_below    : std_logic;
begin
  top <= pushed when top_is_pushed = '1' else below;

  alloc_addr <= free_addr when free = '1' else
                top when depth /= 0 else
                std_logic_vector(fresh(ADDR_BITS - 1 downto 0));

  push <= free and not alloc;
  take <= '1' when alloc = '1' and free = '0' and depth /= 0 else '0';
  -- After a take the new top is entry depth - 2 (entries 0 .. depth - 1 are in the RAM).
  -- (Integer compare: 2 need not fit COUNT_BITS when CAPACITY = 1.)
  read_below <= '1' when take = '1' and to_integer(depth) >= 2 else '0';

  stack : entity work.rq_ram
    generic map (DEPTH => CAPACITY, ADDR_BITS => ADDR_BITS, DATA_BITS => ADDR_BITS)
    port map (
      clk => clk,
      we => push, waddr => std_logic_vector(depth(ADDR_BITS - 1 downto 0)), wdata => free_addr,
      re => read_below, raddr => std_logic_vector(resize(depth - 1, ADDR_BITS) - 1),
      rdata => below);

  regs : process (clk)
  begin
    if rising_edge(clk) then
      if rst = '1' then
        fresh <= (others => '0');
        depth <= (others => '0');
        top_is_pushed <= '0';
      elsif push = '1' then
        depth <= depth + 1;
        pushed <= free_addr;
        top_is_pushed <= '1';
      elsif take = '1' then
        depth <= depth - 1;
        top_is_pushed <= '0';
      elsif alloc = '1' and free = '0' then
        fresh <= fresh + 1;  -- the LIFO is empty: a never-used address
      end if;
    end if;
  end process regs;
end architecture rtl;
