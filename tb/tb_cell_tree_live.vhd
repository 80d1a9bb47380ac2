-- tb_cell_tree_live: cell_tree (fpga/rtl/cell_tree.vhd) against the C model running beside it
-- (c5ref_ct_*, the model's c5_ctree_tag; docs/vectors.md, "The model inside the simulator").
--
-- Drives:  from an empty tree of CAPACITY slots (small, so that the RAM overflows and freezes
--          within the run), TAGS packets drawn from SEED alone, one at a time with in_valid
--          while in_ready = 1: a quarter with no node yet, the others tagged with a node the
--          tree has answered before; cells mostly from 16 (many children a node: extension
--          slots), some from 64 or all 4,096. At the end rd_slot and rd_cell.
-- Checks:  per tag node_out, used and frozen = the model's; at the end every used RAM slot
--          and every root through the readback ports. The first difference ends the run:
--          "FAIL tb_cell_tree_live: seed S tag N: PORT: model X, VHDL Y".
-- Latency: variable (cell_tree.vhd has the formula); out_valid within 2^14 cycles.
-- Usage:   ghdl -r --std=08 tb_cell_tree_live -gSEED=1 -gTAGS=3000 (./libc5ref.so beside)
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use work.c5_layouts_pkg.all;
use work.c5ref_pkg.all;
use work.tb_pkg.all;

entity tb_cell_tree_live is
  generic (SEED : positive := 1; TAGS : positive := 3000; CAPACITY : positive := 400);
end entity tb_cell_tree_live;

architecture sim of tb_cell_tree_live is
  constant TB : string := "tb_cell_tree_live";
  constant AT : string := live_at(TB, SEED, "tag");
  constant ID_BITS : positive := RAY_PACKET_CELL_TREE_NODE_WIDTH;
  constant NONE : natural := 2 ** ID_BITS - 1;
  constant CELLS : positive := 2 ** RAY_PACKET_CELL_ID_WIDTH;
  signal clk, rst, in_valid, in_ready, out_valid, frozen : std_logic := '0';
  signal node_in, node_out, rd_slot, rd_root : std_logic_vector(ID_BITS - 1 downto 0) := (others => '0');
  signal cell, rd_cell : std_logic_vector(RAY_PACKET_CELL_ID_WIDTH - 1 downto 0) := (others => '0');
  signal used : std_logic_vector(ID_BITS downto 0);
  signal rd_node : CELL_TREE_NODE_T;
begin
  dut : entity work.cell_tree
    generic map (CAPACITY => CAPACITY)
    port map (clk => clk, rst => rst, in_valid => in_valid, in_ready => in_ready,
              node_in => node_in, cell => cell, out_valid => out_valid, node_out => node_out,
              used => used, frozen => frozen, rd_slot => rd_slot, rd_cell => rd_cell,
              rd_node => rd_node, rd_root => rd_root);

  run : process
    variable rnd : random_t;
    type ids_t is array (0 to 2 ** ID_BITS - 1) of natural;
    variable known : ids_t;
    variable nknown, ni, ci, model, rc, waited : natural := 0;
    variable seen : boolean;
  begin
    rnd.seed(SEED);
    rc := c5ref_ct_reset(CAPACITY);
    reset(clk, rst);
    while in_ready /= '1' loop  -- the root table's clearing
      tick(clk);
    end loop;
    for n in 0 to TAGS - 1 loop
      ni := NONE;
      if nknown > 0 and rnd.pick(4) /= 0 then
        ni := known(rnd.pick(nknown));
      end if;
      case rnd.pick(10) is
        when 0 => ci := rnd.pick(CELLS);
        when 1 | 2 => ci := rnd.pick(64);
        when others => ci := rnd.pick(16);
      end case;
      model := c5ref_ct_tag(ni, ci);
      node_in <= std_logic_vector(to_unsigned(ni, ID_BITS));
      cell <= std_logic_vector(to_unsigned(ci, cell'length));
      in_valid <= '1';
      wait for HALF;
      live_expect(AT, n, "in_ready", 1, live_bit(in_ready));
      edge(clk);
      in_valid <= '0';
      await_out(clk, out_valid, 2 ** 14, waited);
      live_expect(AT, n, "out_valid within 2^14 cycles", 1, live_bit(out_valid));
      live_expect(AT, n, "node_out", model, to_integer(unsigned(node_out)));
      live_expect(AT, n, "used", c5ref_ct_state(0), to_integer(unsigned(used)));
      live_expect(AT, n, "frozen", c5ref_ct_state(1), live_bit(frozen));
      if model /= NONE then
        seen := false;
        for k in 0 to nknown - 1 loop
          seen := seen or known(k) = model;
        end loop;
        if not seen then
          known(nknown) := model;
          nknown := nknown + 1;
        end if;
      end if;
      edge(clk);
    end loop;
    tick(clk);  -- the last write-back
    for slot in 0 to c5ref_ct_state(0) - 1 loop
      rd_slot <= std_logic_vector(to_unsigned(slot, ID_BITS));
      tick(clk);
      tick(clk);
      for w in 0 to 2 loop
        live_expect(live_at(TB, SEED, "slot"), slot, "rd_node word " & integer'image(w),
                    c5ref_ct_slot_word(slot, w), to_integer(signed(rd_node(32 * w + 31 downto 32 * w))));
      end loop;
    end loop;
    for c in 0 to CELLS - 1 loop
      rd_cell <= std_logic_vector(to_unsigned(c, rd_cell'length));
      tick(clk);
      tick(clk);
      live_expect(live_at(TB, SEED, "cell"), c, "rd_root", c5ref_ct_root(c), to_integer(unsigned(rd_root)));
    end loop;
    live_pass(TB, SEED, integer'image(TAGS) & " tags, " & integer'image(c5ref_ct_state(0)) & " slots, frozen " &
              integer'image(c5ref_ct_state(1)));
  end process run;
end architecture sim;
