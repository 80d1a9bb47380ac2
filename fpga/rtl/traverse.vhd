-- Block "traverse": one step of the processor's traversal loop over the active cell
-- (rtl_model/proc/processor.c trav_step, c5_trav_step), bit for bit:
--   leave  (action 2): lifetime 0, or pos outside the grid [0, dims) or the cell [lo, hi)
--          (in voxels, pos >> 15): everything passes unchanged, leaped 0;
--   leap   (action 1): pos's 8^3 block is empty: n = the smallest step count that carries
--          pos out of the block's box clipped to the cell, per axis with S_a /= 0
--          ceil((hi_a 2^15 - pos_a) / S_a) (S_a > 0) or floor((pos_a - lo_a 2^15) / -S_a) + 1
--          (S_a < 0), the least over the axes (at least 1); n is cut to the lifetime
--          unless that is 4095 (unbounded); pos += n S, lifetime -= n, leaped = n;
--   sample (action 0): pos += S, lifetime -= 1 (unless 4095), leaped 0.
-- The divisions are of non-negative numbers (pos is inside the box), so C's truncating
-- division is the floor here. With S = 0 on every axis the model's n is INT64_MAX: leaped
-- is then its low LEAPED_BITS bits (all ones), and the lifetime cut as usual.
--
-- Pipeline: TRAVERSE_LATENCY = 3 (dp_pkg). Stage 1: the grid, cell and block box tests and
-- the dividends; stage 2: three restoring dividers (combinational, LEAPED_BITS + 1
-- quotient bits) and their least; stage 3: the lifetime cut, pos + n S, the outputs. One
-- step a cycle; rst clears only the valid bits.
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

library work;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;

entity traverse is
  port (
    clk, rst     : in  std_logic;
    in_valid     : in  std_logic;
    pos          : in  pos3_t;    -- grid_pos SQ13.15, voxel coordinates
    step         : in  step3_t;   -- step_vec SQ3.15
    lifetime     : in  std_logic_vector(RAY_PACKET_LIFETIME_WIDTH - 1 downto 0);
    cell_lo      : in  grid3_t;   -- the cell's voxel box [lo, hi)
    cell_hi      : in  grid3_t;
    dims         : in  grid3_t;   -- the grid
    block_empty  : in  std_logic; -- of pos's 8^3 block
    out_valid    : out std_logic;
    action       : out std_logic_vector(1 downto 0);  -- 0 sample, 1 leap, 2 leave
    leaped       : out std_logic_vector(LEAPED_BITS - 1 downto 0);
    pos_out      : out pos3_t;
    lifetime_out : out std_logic_vector(RAY_PACKET_LIFETIME_WIDTH - 1 downto 0));
end entity traverse;

architecture rtl of traverse is
  constant SAMPLE : std_logic_vector(1 downto 0) := "00";
  constant LEAP   : std_logic_vector(1 downto 0) := "01";
  constant LEAVE  : std_logic_vector(1 downto 0) := "10";
  constant Q_BITS : positive := LEAPED_BITS + 1;     -- n <= 2^18 (a box of 8 voxels, |S| >= 1)
  constant W_BITS : positive := POS_BITS + 3;        -- box edges and dividends, signed
  subtype num_t is unsigned(Q_BITS downto 0);        -- a dividend: < 2^18 + 2^18
  subtype den_t is unsigned(SIG_STEP_VEC_WIDTH - 2 downto 0);  -- |S_a| <= 2^18
  subtype n_t   is unsigned(Q_BITS downto 0);        -- a step count; all ones: no axis moves
  type num3_t is array (0 to 2) of num_t;
  type den3_t is array (0 to 2) of den_t;

  -- floor(n / d), d > 0: restoring division, one quotient bit an iteration
  function udiv(n : num_t; d : den_t) return n_t is
    variable r : unsigned(den_t'length + 1 downto 0) := (others => '0');
    variable q : n_t := (others => '0');
  begin
    for i in num_t'length - 1 downto 0 loop
      r := r(r'high - 1 downto 0) & n(i);
      if r >= resize(d, r'length) then
        r := r - resize(d, r'length);
        q(i) := '1';
      end if;
    end loop;
    return q;
  end function udiv;

  signal s1_valid : std_logic := '0';
  signal s1_act   : std_logic_vector(1 downto 0) := LEAVE;
  signal s1_pos   : pos3_t := (others => (others => '0'));
  signal s1_step  : step3_t := (others => (others => '0'));
  signal s1_life  : std_logic_vector(lifetime'range) := (others => '0');
  signal s1_num   : num3_t := (others => (others => '0'));
  signal s1_den   : den3_t := (others => (others => '0'));
  signal s1_up    : std_logic_vector(0 to 2) := (others => '0');  -- S_a < 0: + 1
  signal s2_valid : std_logic := '0';
  signal s2_act   : std_logic_vector(1 downto 0) := LEAVE;
  signal s2_pos   : pos3_t := (others => (others => '0'));
  signal s2_step  : step3_t := (others => (others => '0'));
  signal s2_life  : std_logic_vector(lifetime'range) := (others => '0');
  signal s2_n     : n_t := (others => '0');
begin
  process (clk)
    variable p, e, lo, hi, v, b, blo, bhi, num : signed(W_BITS - 1 downto 0);
    variable sa     : signed(SIG_STEP_VEC_WIDTH - 1 downto 0);
    variable inside : boolean;
    variable m, n   : n_t;
    variable life   : unsigned(lifetime'range);
    variable np     : signed(W_BITS + Q_BITS + SIG_STEP_VEC_WIDTH downto 0);
  begin
    if rising_edge(clk) then
      -- stage 1: the tests and the dividends
      inside := true;
      for a in 0 to 2 loop
        p := resize(signed(pos(a)), W_BITS);
        e := shift_left(signed(resize(unsigned(dims(a)), W_BITS)), POS_FRAC);
        lo := signed(resize(unsigned(cell_lo(a)), W_BITS));
        hi := signed(resize(unsigned(cell_hi(a)), W_BITS));
        v := shift_right(p, POS_FRAC);                 -- the voxel (floor)
        if p < 0 or p >= e or v < lo or v >= hi then
          inside := false;
        end if;
        b := shift_left(shift_right(v, BLOCK_BITS), BLOCK_BITS);  -- the block's first voxel
        blo := b;
        if lo > b then
          blo := lo;
        end if;
        bhi := b + 2 ** BLOCK_BITS;
        if hi < bhi then
          bhi := hi;
        end if;
        sa := signed(step(a));
        if sa > 0 then
          num := shift_left(bhi, POS_FRAC) - p + sa - 1;
        else
          num := p - shift_left(blo, POS_FRAC);
        end if;
        s1_num(a) <= unsigned(num(num_t'range));
        s1_den(a) <= resize(magnitude(sa), den_t'length);
        s1_up(a) <= '1' when sa < 0 else '0';
      end loop;
      if unsigned(lifetime) = 0 or not inside then
        s1_act <= LEAVE;
      elsif block_empty = '1' then
        s1_act <= LEAP;
      else
        s1_act <= SAMPLE;
      end if;
      s1_pos <= pos;
      s1_step <= step;
      s1_life <= lifetime;
      s1_valid <= in_valid;

      -- stage 2: the dividers and the least count
      n := (others => '1');
      for a in 0 to 2 loop
        if s1_den(a) /= 0 then
          m := udiv(s1_num(a), s1_den(a));
          if s1_up(a) = '1' then
            m := m + 1;
          end if;
          if m < n then
            n := m;
          end if;
        end if;
      end loop;
      if n = 0 then
        n := to_unsigned(1, n'length);
      end if;
      if s1_act = SAMPLE then
        n := to_unsigned(1, n'length);
      elsif s1_act = LEAVE then
        n := (others => '0');
      end if;
      s2_n <= n;
      s2_act <= s1_act;
      s2_pos <= s1_pos;
      s2_step <= s1_step;
      s2_life <= s1_life;
      s2_valid <= s1_valid;

      -- stage 3: the lifetime cut and the advance
      n := s2_n;
      life := unsigned(s2_life);
      if life /= LIFE_NONE and n > resize(life, n'length) then
        n := resize(life, n'length);
      end if;
      for a in 0 to 2 loop
        np := resize(signed(s2_pos(a)), np'length) + resize(signed('0' & n) * signed(s2_step(a)), np'length);
        pos_out(a) <= std_logic_vector(np(POS_BITS - 1 downto 0));
      end loop;
      if life /= LIFE_NONE then
        life := life - resize(n, life'length);
      end if;
      lifetime_out <= std_logic_vector(life);
      if s2_act = LEAP then
        leaped <= std_logic_vector(n(LEAPED_BITS - 1 downto 0));
      else
        leaped <= (others => '0');
      end if;
      action <= s2_act;
      out_valid <= s2_valid;
      if rst = '1' then
        s1_valid <= '0';
        s2_valid <= '0';
        out_valid <= '0';
      end if;
    end if;
  end process;
end architecture rtl;
