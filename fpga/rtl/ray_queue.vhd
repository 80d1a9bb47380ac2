-- The ray queue: one cell's pipelined insertion sorter on its eDRAM, cycle-exact to the C
-- model rtl_model/proc/ray_queue.c (docs/ray-queue.md). Same ports, same latency rule: every
-- output of cycle t comes from the registers at the start of t and the inputs of t.
--
--   pop_valid       = pop_ready and count > 0; pop_key / pop_payload are 0 otherwise
--   full            = count = CAPACITY and not pop_valid
--   insert_accepted = insert_valid and not full
--   count, empty    = the occupancy at the start of the cycle (held + in flight)
--
-- As in the paper, only the key and an eDRAM address travel through the CAPACITY stages
-- (rq_stage.vhd); the payload (in the board: the 32-byte ray packet) is written once into
-- the payload RAM at an address from rq_addr_alloc.vhd and read once, when its element
-- leaves. The RAM reads synchronously (block RAM, eDRAM), but pop_payload is due in the
-- same cycle as pop_valid: so at every edge the RAM reads the address of the next
-- cycle's head, held'[0], into its output register (a prefetch), and when held'[0] is the
-- element inserted at that very edge, whose payload is only being written, the payload is
-- taken from the insert port instead (the bypass).
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

library work;
use work.rq_pkg.all;

entity ray_queue is
  generic (
    CAPACITY     : positive := 256;  -- stages = elements held (the board: 256)
    KEY_BITS     : positive := 32;   -- smaller key = served first
    PAYLOAD_BITS : positive := 32);  -- carried unchanged, in the payload RAM
  port (
    clk             : in  std_logic;
    rst             : in  std_logic;  -- synchronous: the queue empties
    insert_valid    : in  std_logic;
    insert_key      : in  std_logic_vector(KEY_BITS - 1 downto 0);
    insert_payload  : in  std_logic_vector(PAYLOAD_BITS - 1 downto 0);
    pop_ready       : in  std_logic;  -- take the head element this cycle if there is one
    pop_valid       : out std_logic;
    pop_key         : out std_logic_vector(KEY_BITS - 1 downto 0);
    pop_payload     : out std_logic_vector(PAYLOAD_BITS - 1 downto 0);
    insert_accepted : out std_logic;
    full            : out std_logic;  -- an insert this cycle is (or would be) refused
    count           : out std_logic_vector(clog2(CAPACITY + 1) - 1 downto 0);
    empty           : out std_logic);
end entity ray_queue;

architecture rtl of ray_queue is
  constant ADDR_BITS  : positive := clog2(CAPACITY);
  constant COUNT_BITS : positive := clog2(CAPACITY + 1);

  subtype key_t is std_logic_vector(KEY_BITS - 1 downto 0);
  subtype addr_t is std_logic_vector(ADDR_BITS - 1 downto 0);
  type key_arr is array (natural range <>) of key_t;
  type addr_arr is array (natural range <>) of addr_t;

  -- carry(i) enters stage i: carry(0) is the insert port, carry(i + 1) stage i's register.
  -- h(i) is stage i's held register, cf(i) its level-1 result (carry(i) goes before h(i));
  -- h(CAPACITY) and cf(CAPACITY) are the empty end of the line.
  signal c_v, c_f : std_logic_vector(0 to CAPACITY);
  signal c_k      : key_arr(0 to CAPACITY);
  signal c_a      : addr_arr(0 to CAPACITY);
  signal h_v      : std_logic_vector(0 to CAPACITY);
  signal h_k      : key_arr(0 to CAPACITY);
  signal h_a      : addr_arr(0 to CAPACITY);
  signal cf       : std_logic_vector(0 to CAPACITY);
  signal next_a   : addr_arr(0 to CAPACITY - 1);
  signal next_c   : std_logic_vector(0 to CAPACITY - 1);

  signal cnt      : unsigned(COUNT_BITS - 1 downto 0) := (others => '0');
  signal pop      : std_logic;
  signal accepted : std_logic;
  signal ins_addr : addr_t;

  -- the head's payload, prefetched (see the header)
  signal ram_head       : std_logic_vector(PAYLOAD_BITS - 1 downto 0);
  signal bypass_payload : std_logic_vector(PAYLOAD_BITS - 1 downto 0) := (others => '0');
  signal head_is_bypass : std_logic := '0';
  signal head_payload   : std_logic_vector(PAYLOAD_BITS - 1 downto 0);
begin
  -- ---- control: the C model's c5_rq_step outputs --------------------------------------
  pop      <= '1' when pop_ready = '1' and cnt /= 0 else '0';
  full     <= '1' when cnt = CAPACITY and pop = '0' else '0';
  accepted <= '1' when insert_valid = '1' and not (cnt = CAPACITY and pop = '0') else '0';

  pop_valid       <= pop;
  pop_key         <= h_k(0) when pop = '1' else (others => '0');
  pop_payload     <= head_payload when pop = '1' else (others => '0');
  insert_accepted <= accepted;
  count           <= std_logic_vector(cnt);
  empty           <= '1' when cnt = 0 else '0';

  counter : process (clk)
  begin
    if rising_edge(clk) then
      if rst = '1' then
        cnt <= (others => '0');
      elsif accepted = '1' and pop = '0' then
        cnt <= cnt + 1;
      elsif accepted = '0' and pop = '1' then
        cnt <= cnt - 1;
      end if;
    end if;
  end process counter;

  -- ---- the sorter: keys and addresses ---------------------------------------------------
  c_v(0) <= accepted;
  c_f(0) <= '1';         -- an inserted element is fresh until it settles
  c_k(0) <= insert_key;
  c_a(0) <= ins_addr;
  h_v(CAPACITY) <= '0';   -- past the last stage: nothing
  h_k(CAPACITY) <= (others => '0');
  h_a(CAPACITY) <= (others => '0');
  cf(CAPACITY)  <= '0';

  stages : for i in 0 to CAPACITY - 1 generate
    stage : entity work.rq_stage
      generic map (KEY_BITS => KEY_BITS, ADDR_BITS => ADDR_BITS, FIRST => i = 0)
      port map (
        clk => clk, rst => rst, pop => pop,
        c_valid => c_v(i), c_fresh => c_f(i), c_key => c_k(i), c_addr => c_a(i),
        nh_valid => h_v(i + 1), nh_key => h_k(i + 1), nh_addr => h_a(i + 1),
        n_c_first => cf(i + 1), c_first_out => cf(i),
        held_valid => h_v(i), held_key => h_k(i), held_addr => h_a(i),
        carry_valid => c_v(i + 1), carry_fresh => c_f(i + 1),
        carry_key => c_k(i + 1), carry_addr => c_a(i + 1),
        next_addr => next_a(i), next_is_c => next_c(i));
  end generate stages;
  -- carry(CAPACITY), the last stage's carry register, stays empty: count <= CAPACITY means
  -- nothing is ever pushed off the end of the line. Synthesis drops it (no reader).

  -- ---- the eDRAM: payloads at allocated addresses ---------------------------------------
  alloc : entity work.rq_addr_alloc
    generic map (CAPACITY => CAPACITY, ADDR_BITS => ADDR_BITS, COUNT_BITS => COUNT_BITS)
    port map (
      clk => clk, rst => rst,
      alloc => accepted, free => pop, free_addr => h_a(0), alloc_addr => ins_addr);

  payload_ram : entity work.rq_ram
    generic map (DEPTH => CAPACITY, ADDR_BITS => ADDR_BITS, DATA_BITS => PAYLOAD_BITS)
    port map (
      clk => clk,
      we => accepted, waddr => ins_addr, wdata => insert_payload,
      re => '1', raddr => next_a(0),   -- prefetch: the payload of held'[0]
      rdata => ram_head);

  -- The bypass: held'[0] is the insert of this edge (stage 0's next_is_c), whose RAM
  -- write lands only at this edge, so keep the insert's payload beside the RAM read.
  bypass : process (clk)
  begin
    if rising_edge(clk) then
      bypass_payload <= insert_payload;
      if rst = '1' then
        head_is_bypass <= '0';
      else
        head_is_bypass <= next_c(0);
      end if;
    end if;
  end process bypass;
  head_payload <= bypass_payload when head_is_bypass = '1' else ram_head;
end architecture rtl;
