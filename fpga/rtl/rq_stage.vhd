-- One stage of the ray queue's pipelined insertion sorter (docs/ray-queue.md): stage i
-- owns two registers, held[i] (the settled element) and carry[i+1] (the element that
-- enters stage i+1 at the next edge), and makes at most two compare-exchanges per cycle.
--
--   level 1, every cycle: the carry entering this stage (c = carry[i]; for stage 0 the
--     insert port) meets held[i]: lo = the one that goes first, hi = the other.
--   no pop: held'[i] = lo, carry'[i+1] = hi.
--   pop (a broadcast: held[0] leaves, the line shifts up one stage): x = hi (stage 0: the
--     insert itself, which takes the place of hi[0]) meets y = lo[i+1], the next stage's
--     level-1 lo: held'[i] = the one that goes first, carry'[i+1] = the other.
--
-- This is rtl_model/ray_queue.c written per stage, every stage every cycle; the C model
-- skips stages where nothing moves, which changes no register (an empty carry meeting
-- held[i] gives held'[i] = held[i] and an empty carry'[i+1]). Only carries hold `fresh`:
-- a held element is never fresh, so held[i] has no fresh bit. The element is its key and
-- its eDRAM address; the payload stays in the RAM (ray_queue.vhd).
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
    -- lo[i+1] from the next stage's level 1 (tie it empty at the last stage)
    nlo_valid        : in std_logic;
    nlo_key          : in std_logic_vector(KEY_BITS - 1 downto 0);
    nlo_addr         : in std_logic_vector(ADDR_BITS - 1 downto 0);
    -- lo[i], this stage's level-1 result, for the previous stage's level 2
    lo_valid         : out std_logic;
    lo_key           : out std_logic_vector(KEY_BITS - 1 downto 0);
    lo_addr          : out std_logic_vector(ADDR_BITS - 1 downto 0);
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
  -- level 1
  signal c_first : boolean;
  -- what the edge loads
  signal d_h_v, d_r_v, d_r_f, d_is_c : std_logic;
  signal d_h_k, d_r_k : std_logic_vector(KEY_BITS - 1 downto 0);
  signal d_h_a, d_r_a : std_logic_vector(ADDR_BITS - 1 downto 0);
begin
  -- Level 1: the held element is never fresh, so only c's tag matters.
  c_first  <= goes_first(c_valid, c_fresh, c_key, h_v, h_k);
  lo_valid <= c_valid when c_first else h_v;
  lo_key   <= c_key   when c_first else h_k;
  lo_addr  <= c_addr  when c_first else h_a;

  next_state : process (all)
    -- hi of level 1 (its fresh tag: c's when c lost, 0 for a displaced held element)
    variable hi_v, hi_f : std_logic;
    variable hi_k : std_logic_vector(KEY_BITS - 1 downto 0);
    variable hi_a : std_logic_vector(ADDR_BITS - 1 downto 0);
    -- level 2: x meets y = lo[i+1]
    variable x_v, x_f : std_logic;
    variable x_k : std_logic_vector(KEY_BITS - 1 downto 0);
    variable x_a : std_logic_vector(ADDR_BITS - 1 downto 0);
  begin
    if c_first then
      hi_v := h_v; hi_f := '0'; hi_k := h_k; hi_a := h_a;
    else
      hi_v := c_valid; hi_f := c_fresh and c_valid; hi_k := c_key; hi_a := c_addr;
    end if;

    if pop = '1' then
      if FIRST then
        x_v := c_valid; x_f := c_fresh and c_valid; x_k := c_key; x_a := c_addr;
      else
        x_v := hi_v; x_f := hi_f; x_k := hi_k; x_a := hi_a;
      end if;
      if goes_first(x_v, x_f, x_k, nlo_valid, nlo_key) then
        -- x settles here (no longer fresh); lo[i+1] moves on, never fresh
        d_h_v <= x_v; d_h_k <= x_k; d_h_a <= x_a;
        d_r_v <= nlo_valid; d_r_f <= '0'; d_r_k <= nlo_key; d_r_a <= nlo_addr;
        if FIRST then
          d_is_c <= '1';               -- x is the insert
        elsif c_first then
          d_is_c <= '0';               -- x is the displaced held[i]
        else
          d_is_c <= c_valid;           -- x is c, which lost level 1
        end if;
      else
        d_h_v <= nlo_valid; d_h_k <= nlo_key; d_h_a <= nlo_addr;
        d_r_v <= x_v; d_r_f <= x_f; d_r_k <= x_k; d_r_a <= x_a;
        d_is_c <= '0';
      end if;
    else
      if c_first then
        d_h_v <= c_valid; d_h_k <= c_key; d_h_a <= c_addr;
        d_is_c <= '1';
      else
        d_h_v <= h_v; d_h_k <= h_k; d_h_a <= h_a;
        d_is_c <= '0';
      end if;
      d_r_v <= hi_v; d_r_f <= hi_f; d_r_k <= hi_k; d_r_a <= hi_a;
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
