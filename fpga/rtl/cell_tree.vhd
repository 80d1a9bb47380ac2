-- The Cell Tree tagging unit (rtl_model/dsp/cell_tree.c c5_ctree_tag; docs/cell-tree.md),
-- bit for bit: a ray packet on its way to the queue of `cell`, tagged with `node_in`
-- (all ones = none), gets node_out:
--   the tree is frozen (a node did not fit): none;
--   node_in none: the cell's root, made on first use (one slot);
--   node_in's cell is `cell`: node_in (the ray stays in its cell);
--   else node_in's child for `cell`, found by walking its child list (five ids a slot; a
--   chained slot's last id is its extension slot), or made at the list's first free id,
--   or, in a full slot, made with an extension slot that takes the slot's last child and
--   the new one (two slots), the slot then chained.
-- Slots are taken in order (used, the next free id) up to CAPACITY (8,191: id 8191 is
-- none); a slot that does not fit freezes the tree. Every node is a cell_tree_node
-- (spec/layouts.toml, packed by the generated cell_tree_node_pack / _unpack): a fresh one
-- is all zero but its cell and five none children.
--
-- Memories: the node RAM (2^13 slots x 96 bits: the DSP's 96 KB) and the root table
-- (2^12 cells x 13 bits), each one port with a registered read (block RAM). After rst the
-- unit clears the root table (2^12 cycles, in_ready 0): the empty tree of a new frame.
--
-- A multi-cycle unit: one RAM access a cycle, a read's data two cycles after its address
-- is set (the address register, then the RAM's read register). A tag accepted in cycle 0
-- (in_valid and in_ready) gives out_valid (one cycle) with node_out in cycle
--   1                      frozen tree,
--   3                      node_in none (root), or node_in of the same cell,
--   3 + 3 (c + e)          a child found after reading c children and e extension slots,
--   3 + 3 (c + e) + 3      a child made (+ 1 when it takes an extension slot; 3 + 3 (c + e)
--                          + 2 when it does not fit and freezes the tree).
-- The readback ports (rd_*) read the node RAM and the root table
-- while the unit is idle: the testbench compares the final images through them.
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

library work;
use work.c5_layouts_pkg.all;

entity cell_tree is
  generic (CAPACITY : positive := 2 ** RAY_PACKET_CELL_TREE_NODE_WIDTH - 1);
  port (
    clk, rst   : in  std_logic;
    in_valid   : in  std_logic;
    in_ready   : out std_logic;
    node_in    : in  std_logic_vector(RAY_PACKET_CELL_TREE_NODE_WIDTH - 1 downto 0);
    cell       : in  std_logic_vector(RAY_PACKET_CELL_ID_WIDTH - 1 downto 0);
    out_valid  : out std_logic;
    node_out   : out std_logic_vector(RAY_PACKET_CELL_TREE_NODE_WIDTH - 1 downto 0);
    used       : out std_logic_vector(RAY_PACKET_CELL_TREE_NODE_WIDTH downto 0);  -- slots taken
    frozen     : out std_logic;                                                 -- overflowed
    -- readback while idle: node RAM slot rd_slot, root of cell rd_cell, one cycle later
    rd_slot    : in  std_logic_vector(RAY_PACKET_CELL_TREE_NODE_WIDTH - 1 downto 0);
    rd_cell    : in  std_logic_vector(RAY_PACKET_CELL_ID_WIDTH - 1 downto 0);
    rd_node    : out CELL_TREE_NODE_T;
    rd_root    : out std_logic_vector(RAY_PACKET_CELL_TREE_NODE_WIDTH - 1 downto 0));
end entity cell_tree;

architecture rtl of cell_tree is
  constant ID_BITS  : positive := RAY_PACKET_CELL_TREE_NODE_WIDTH;
  constant SLOTS    : positive := 2 ** ID_BITS;
  constant N_ROOTS  : positive := 2 ** RAY_PACKET_CELL_ID_WIDTH;
  constant N_KIDS   : positive := 5;  -- child ids a slot
  subtype id_t is unsigned(ID_BITS - 1 downto 0);
  constant NONE     : id_t := (others => '1');
  type ram_t  is array (0 to SLOTS - 1) of CELL_TREE_NODE_T;
  type root_t is array (0 to N_ROOTS - 1) of std_logic_vector(ID_BITS - 1 downto 0);
  type kids_t is array (0 to N_KIDS - 1) of id_t;

  signal ram   : ram_t;
  signal roots : root_t;
  -- one port each: address, write enable and data, the read data a cycle later
  signal ram_a : natural range 0 to SLOTS - 1 := 0;
  signal ram_we : std_logic := '0';
  signal ram_d, ram_q : CELL_TREE_NODE_T;
  signal root_a : natural range 0 to N_ROOTS - 1 := 0;
  signal root_we : std_logic := '0';
  signal root_d, root_q : std_logic_vector(ID_BITS - 1 downto 0);

  type state_t is (CLEAR, IDLE, RD_WAIT, ROOT_RD, NODE_RD, SCAN, CHILD_RD, SLOT_RD, ALLOC,
                   ALLOC2, WRITE_BACK);
  signal st      : state_t := CLEAR;
  signal then_st : state_t := IDLE;                   -- the state a read's data goes to
  signal clr     : natural range 0 to N_ROOTS - 1 := 0;
  signal n_used  : unsigned(ID_BITS downto 0) := (others => '0');
  signal over    : boolean := false;
  signal t_node  : id_t := NONE;                      -- the tag
  signal t_cell  : std_logic_vector(cell'range) := (others => '0');
  signal slot    : id_t := (others => '0');           -- the list slot being walked
  signal cur     : cell_tree_node_rec;                -- its content
  signal ki      : natural range 0 to N_KIDS := 0;      -- the child being looked at
  signal res     : id_t := NONE;

  function kids(n : cell_tree_node_rec) return kids_t is
  begin
    return (unsigned(n.child0), unsigned(n.child1), unsigned(n.child2), unsigned(n.child3),
            unsigned(n.child4));
  end function kids;

  function with_kids(n : cell_tree_node_rec; k : kids_t) return cell_tree_node_rec is
    variable r : cell_tree_node_rec := n;
  begin
    r.child0 := std_logic_vector(k(0));
    r.child1 := std_logic_vector(k(1));
    r.child2 := std_logic_vector(k(2));
    r.child3 := std_logic_vector(k(3));
    r.child4 := std_logic_vector(k(4));
    return r;
  end function with_kids;

  -- a new node of cell c: all zero but the cell and five none children
  function fresh(c : std_logic_vector) return cell_tree_node_rec is
    variable r : cell_tree_node_rec;
  begin
    r := cell_tree_node_unpack((others => '0'));
    r.cell_id := c;
    return with_kids(r, (others => NONE));
  end function fresh;
begin
  in_ready <= '1' when st = IDLE else '0';
  used <= std_logic_vector(n_used);
  frozen <= '1' when over else '0';
  rd_node <= ram_q;
  rd_root <= root_q;

  memories : process (clk)
  begin
    if rising_edge(clk) then
      if ram_we = '1' then
        ram(ram_a) <= ram_d;
      end if;
      ram_q <= ram(ram_a);
      if root_we = '1' then
        roots(root_a) <= root_d;
      end if;
      root_q <= roots(root_a);
    end if;
  end process memories;

  fsm : process (clk)
    variable n : cell_tree_node_rec;
    variable k : kids_t;
    variable last : natural range 0 to N_KIDS;
    variable free : natural range 0 to N_KIDS;
    variable ext : cell_tree_node_rec;

    -- a read issued this cycle (the address register set): its data in state s, two
    -- cycles on (the RAM's read register, as a block RAM's output register)
    procedure read_then(s : state_t) is
    begin
      then_st <= s;
      st <= RD_WAIT;
    end procedure read_then;

    procedure finish(r : id_t) is
    begin
      node_out <= std_logic_vector(r);
      out_valid <= '1';
      st <= IDLE;
    end procedure finish;

  begin
    if rising_edge(clk) then
      out_valid <= '0';
      ram_we <= '0';
      root_we <= '0';
      case st is
        when CLEAR =>  -- every root none
          root_a <= clr;
          root_d <= std_logic_vector(NONE);
          root_we <= '1';
          if clr = N_ROOTS - 1 then
            st <= IDLE;
          else
            clr <= clr + 1;
          end if;

        when IDLE =>
          ram_a <= to_integer(unsigned(rd_slot));
          root_a <= to_integer(unsigned(rd_cell));
          if in_valid = '1' then
            t_node <= unsigned(node_in);
            t_cell <= cell;
            if over then
              finish(NONE);
            elsif unsigned(node_in) = NONE then
              root_a <= to_integer(unsigned(cell));
              read_then(ROOT_RD);
            else
              ram_a <= to_integer(unsigned(node_in));
              read_then(NODE_RD);
            end if;
          end if;

        when RD_WAIT =>  -- the address is in the RAM's port: the data comes next cycle
          st <= then_st;

        when ROOT_RD =>
          if unsigned(root_q) /= NONE then
            finish(unsigned(root_q));
          elsif n_used + 1 > CAPACITY then
            over <= true;
            finish(NONE);
          else  -- the cell's root, in the next free slot
            ram_a <= to_integer(n_used);
            ram_d <= cell_tree_node_pack(fresh(t_cell));
            ram_we <= '1';
            root_d <= std_logic_vector(n_used(ID_BITS - 1 downto 0));
            root_we <= '1';
            n_used <= n_used + 1;
            finish(n_used(ID_BITS - 1 downto 0));
          end if;

        when NODE_RD =>
          n := cell_tree_node_unpack(ram_q);
          if n.cell_id = t_cell then
            finish(t_node);
          else
            slot <= t_node;
            cur <= n;
            ki <= 0;
            st <= SCAN;
          end if;

        -- the next child of the slot, the extension slot, or the end of the list
        when SCAN =>
          k := kids(cur);
          last := N_KIDS;
          if cur.chained = "1" then
            last := N_KIDS - 1;
          end if;
          if ki < last and k(ki mod N_KIDS) /= NONE then
            ram_a <= to_integer(k(ki mod N_KIDS));
            read_then(CHILD_RD);
          elsif cur.chained = "1" then
            slot <= k(N_KIDS - 1);
            ram_a <= to_integer(k(N_KIDS - 1));
            read_then(SLOT_RD);
          else
            st <= ALLOC;
          end if;

        when CHILD_RD =>
          n := cell_tree_node_unpack(ram_q);
          k := kids(cur);
          if n.cell_id = t_cell then
            finish(k(ki mod N_KIDS));
          else
            ki <= ki + 1;
            st <= SCAN;
          end if;

        when SLOT_RD =>
          cur <= cell_tree_node_unpack(ram_q);
          ki <= 0;
          st <= SCAN;

        -- a new child: at the first free id, or with an extension slot
        when ALLOC =>
          k := kids(cur);
          free := N_KIDS;
          for i in N_KIDS - 1 downto 0 loop
            if k(i) = NONE then
              free := i;
            end if;
          end loop;
          if free < N_KIDS then
            if n_used + 1 > CAPACITY then
              over <= true;
              finish(NONE);
            else
              ram_a <= to_integer(n_used);
              ram_d <= cell_tree_node_pack(fresh(t_cell));
              ram_we <= '1';
              k(free) := n_used(ID_BITS - 1 downto 0);
              cur <= with_kids(cur, k);
              res <= n_used(ID_BITS - 1 downto 0);
              n_used <= n_used + 1;
              st <= WRITE_BACK;
            end if;
          elsif n_used + 2 > CAPACITY then
            over <= true;
            finish(NONE);
          else  -- the new node at used + 1; the extension slot (used) next cycle
            ram_a <= to_integer(n_used + 1);
            ram_d <= cell_tree_node_pack(fresh(t_cell));
            ram_we <= '1';
            res <= n_used(ID_BITS - 1 downto 0) + 1;
            st <= ALLOC2;
          end if;

        when ALLOC2 =>
          k := kids(cur);
          ext := fresh(cur.cell_id);
          ext.extension := "1";
          ext.child0 := std_logic_vector(k(N_KIDS - 1));
          ext.child1 := std_logic_vector(res);
          ram_a <= to_integer(n_used);
          ram_d <= cell_tree_node_pack(ext);
          ram_we <= '1';
          k(N_KIDS - 1) := n_used(ID_BITS - 1 downto 0);
          n := with_kids(cur, k);
          n.chained := "1";
          cur <= n;
          n_used <= n_used + 2;
          st <= WRITE_BACK;

        when WRITE_BACK =>  -- the list slot with its new child id
          ram_a <= to_integer(slot);
          ram_d <= cell_tree_node_pack(cur);
          ram_we <= '1';
          finish(res);
      end case;
      if rst = '1' then
        st <= CLEAR;
        clr <= 0;
        n_used <= (others => '0');
        over <= false;
        out_valid <= '0';
      end if;
    end if;
  end process fsm;
end architecture rtl;
