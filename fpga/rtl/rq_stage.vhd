-- One stage of the ray queue's pipelined insertion sorter (docs/ray-queue.md): stage i
-- owns two registers, held[i] (the settled element) and carry[i+1] (the element that
-- enters stage i+1 at the next edge), and decides both from at most two compare-exchanges.
--
--   level 1, every cycle: the carry entering this stage (c = carry[i]; for stage 0 the
--     insert port) meets held[i]: lo = the one that goes first, hi = the other.
--   no pop: held'[i] = lo, carry'[i+1] = hi.
--   pop (a broadcast: held[0] leaves, the line shifts up one stage): x = hi (stage 0: the
--     insert itself, which takes the place of hi[0]) meets y = lo[i+1], the next stage's
--     level-1 lo: held'[i] = the one that goes first, carry'[i+1] = the other.
--
-- This is rtl_model/proc/ray_queue.c written per stage, every stage every cycle; the C model
-- skips stages where nothing moves, which changes no register (an empty carry meeting
-- held[i] gives held'[i] = held[i] and an empty carry'[i+1]).
--
-- Timing: level 2 would compare the results of two level-1 compare-exchanges, two 33-bit
-- carry chains in series (about 41 MHz on an iCE40 HX at capacity 16). Instead every
-- candidate pair is compared at once, straight from the registers, and level 1's results
-- only select: x is held[i] or c, y is carry[i+1] or held[i+1], so level 2 is one of
--   held[i] vs carry[i+1], c vs carry[i+1], c vs held[i+1], and held[i] vs held[i+1],
-- the last of which needs no comparator: the held line is sorted and gap-free, so
-- held[i] goes before held[i+1] exactly when held[i] is valid. Four comparators in
-- parallel (level 1 and three for level 2) instead of two in series: one carry chain deep.
--
-- Only carries hold `fresh`: a held element is never fresh, so held[i] has no fresh bit.
-- The element is its key and its eDRAM address; the payload stays in the RAM
-- (ray_queue.vhd).
library ieee;
use ieee.std_logic_1164.all;

library work;
use work.rq_pkg.all;

entity rq_stage is
  generic (
    KEY_BITS  : positive;
    ADDR_BITS : positive;
    FIRST     : boolean);  -- stage 0: in a pop cycle the carry entering (the insert) is x
  port (
    clk, rst : in std_logic;  -- rst: synchronous, empties both registers
    pop      : in std_logic;  -- held[0] leaves this cycle: shift up, level 2
    -- the carry entering this stage: carry[i], or the insert port for stage 0
    c_valid, c_fresh : in std_logic;
    c_key            : in std_logic_vector(KEY_BITS - 1 downto 0);
    c_addr           : in std_logic_vector(ADDR_BITS - 1 downto 0);
    -- stage i+1: its held register and its level-1 result (whether our carry register
    -- goes before its held element); tie both empty / '0' at the last stage
    nh_valid         : in std_logic;
    nh_key           : in std_logic_vector(KEY_BITS - 1 downto 0);
    nh_addr          : in std_logic_vector(ADDR_BITS - 1 downto 0);
    n_c_first        : in std_logic;
    -- this stage's level-1 result, for stage i-1
    c_first_out      : out std_logic;
    -- held[i]: the register
    held_valid       : out std_logic;
    held_key         : out std_logic_vector(KEY_BITS - 1 downto 0);
    held_addr        : out std_logic_vector(ADDR_BITS - 1 downto 0);
    -- carry[i+1]: the register
    carry_valid      : out std_logic;
    carry_fresh      : out std_logic;
    carry_key        : out std_logic_vector(KEY_BITS - 1 downto 0);
    carry_addr       : out std_logic_vector(ADDR_BITS - 1 downto 0);
    -- held'[i] before the edge, for the payload prefetch of stage 0: its address, and
    -- whether it is the carry entering (for stage 0: the element inserted at this edge)
    next_addr        : out std_logic_vector(ADDR_BITS - 1 downto 0);
    next_is_c        : out std_logic);
end entity rq_stage;

architecture rtl of rq_stage is
  -- the registers; power-on value = reset value (iCE40 flip-flops start at 0)
  signal h_v  : std_logic := '0';
  signal h_k  : std_logic_vector(KEY_BITS - 1 downto 0) := (others => '0');
  signal h_a  : std_logic_vector(ADDR_BITS - 1 downto 0) := (others => '0');
  signal r_v  : std_logic := '0';
  signal r_f  : std_logic := '0';
  signal r_k  : std_logic_vector(KEY_BITS - 1 downto 0) := (others => '0');
  signal r_a  : std_logic_vector(ADDR_BITS - 1 downto 0) := (others => '0');
  -- every comparison of the cycle, in parallel (a held element is never fresh)
  signal c_first : boolean;  -- level 1: c before held[i]
  signal h_r     : boolean;  -- held[i] before carry[i+1]
  signal c_r     : boolean;  -- c before carry[i+1]
  signal c_n     : boolean;  -- c before held[i+1]
  -- what the edge loads
  signal d_h_v, d_r_v, d_r_f, d_is_c : std_logic;
  signal d_h_k, d_r_k : std_logic_vector(KEY_BITS - 1 downto 0);
  signal d_h_a, d_r_a : std_logic_vector(ADDR_BITS - 1 downto 0);
begin
  c_first <= goes_first(c_valid, c_fresh, c_key, h_v, h_k);
  h_r     <= goes_first(h_v, '0', h_k, r_v, r_k);
  c_r     <= goes_first(c_valid, c_fresh, c_key, r_v, r_k);
  c_n     <= goes_first(c_valid, c_fresh, c_key, nh_valid, nh_key);
  c_first_out <= '1' when c_first else '0';

  next_state : process (all)
    variable x_is_c  : boolean;  -- x is c (else held[i])
    variable y_is_r  : boolean;  -- y = lo[i+1] is carry[i+1] (else held[i+1])
    variable x_first : boolean;  -- level 2: x before y
  begin
    if pop = '1' then
      x_is_c := FIRST or not c_first;
      y_is_r := n_c_first = '1';
      -- (if/else rather than conditional variable assignments, which GHDL 2.0 cannot
      -- elaborate inside process (all))
      if x_is_c and y_is_r then
        x_first := c_r;
      elsif x_is_c then
        x_first := c_n;
      elsif y_is_r then
        x_first := h_r;
      else
        x_first := h_v = '1';  -- held[i] vs held[i+1]: the line is sorted
      end if;
      if x_first then
        -- x settles here (no longer fresh); y = lo[i+1] moves on (never fresh)
        if x_is_c then
          d_h_v <= c_valid; d_h_k <= c_key; d_h_a <= c_addr;
        else
          d_h_v <= h_v; d_h_k <= h_k; d_h_a <= h_a;
        end if;
        if y_is_r then
          d_r_v <= r_v; d_r_k <= r_k; d_r_a <= r_a;
        else
          d_r_v <= nh_valid; d_r_k <= nh_key; d_r_a <= nh_addr;
        end if;
        d_r_f <= '0';
        if x_is_c then
          d_is_c <= '1';
        else
          d_is_c <= '0';
        end if;
      else
        -- y settles here; x moves on with its tag (c's own, 0 for a displaced held[i])
        if y_is_r then
          d_h_v <= r_v; d_h_k <= r_k; d_h_a <= r_a;
        else
          d_h_v <= nh_valid; d_h_k <= nh_key; d_h_a <= nh_addr;
        end if;
        if x_is_c then
          d_r_v <= c_valid; d_r_f <= c_fresh and c_valid; d_r_k <= c_key; d_r_a <= c_addr;
        else
          d_r_v <= h_v; d_r_f <= '0'; d_r_k <= h_k; d_r_a <= h_a;
        end if;
        d_is_c <= '0';
      end if;
    elsif c_first then
      -- no pop, c goes before held[i]: c settles, held[i] is displaced into the carry line
      d_h_v <= c_valid; d_h_k <= c_key; d_h_a <= c_addr;
      d_r_v <= h_v; d_r_f <= '0'; d_r_k <= h_k; d_r_a <= h_a;
      d_is_c <= '1';
    else
      -- no pop, held[i] stays; c (valid or not) travels on with its tag
      d_h_v <= h_v; d_h_k <= h_k; d_h_a <= h_a;
      d_r_v <= c_valid; d_r_f <= c_fresh and c_valid; d_r_k <= c_key; d_r_a <= c_addr;
      d_is_c <= '0';
    end if;
  end process next_state;

  regs : process (clk)
  begin
    if rising_edge(clk) then
      if rst = '1' then
        h_v <= '0'; h_k <= (others => '0'); h_a <= (others => '0');
        r_v <= '0'; r_f <= '0'; r_k <= (others => '0'); r_a <= (others => '0');
      else
        h_v <= d_h_v; h_k <= d_h_k; h_a <= d_h_a;
        r_v <= d_r_v; r_f <= d_r_f; r_k <= d_r_k; r_a <= d_r_a;
      end if;
    end if;
  end process regs;

  held_valid  <= h_v;
  held_key    <= h_k;
  held_addr   <= h_a;
  carry_valid <= r_v;
  carry_fresh <= r_f;
  carry_key   <= r_k;
  carry_addr  <= r_a;
  next_addr   <= d_h_a;
  next_is_c   <= d_is_c;
end architecture rtl;
