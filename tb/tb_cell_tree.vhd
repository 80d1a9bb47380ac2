-- tb_cell_tree: cell_tree (fpga/rtl/cell_tree.vhd) against the golden vectors
-- cell_tree.*.hex and the final images cell_tree.SOURCE.ram_final.hex (slots 0..used-1, 96
-- bits a line) and cell_tree.SOURCE.roots_final.hex (line c = cell c).
--
-- Drives:  from the empty tree (the reset edge, then the root table's clearing), one tag at
--          a time: node_in cell with in_valid while in_ready = 1; at the end rd_slot and
--          rd_cell (the readback ports).
-- Checks:  node_out when out_valid comes; then `used` = the lines of the RAM image, every
--          slot = its line, every root = its line. A malformed line is one error and is
--          skipped; no out_valid within LONGEST cycles ends the run.
-- Latency: variable (cell_tree.vhd has the formula); the latencies seen are reported.
-- Usage:   ghdl -r --std=08 tb_cell_tree -gVECTORS=cell_tree.x.hex -gRAM=cell_tree.x.ram_final.hex
--               -gROOTS=cell_tree.x.roots_final.hex
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use std.textio.all;
use work.c5_layouts_pkg.all;
use work.tb_pkg.all;
use work.vec_io_pkg.all;

entity tb_cell_tree is
  generic (VECTORS : string := "cell_tree.hex"; RAM : string := "cell_tree.ram_final.hex";
           ROOTS : string := "cell_tree.roots_final.hex");
end entity tb_cell_tree;

architecture sim of tb_cell_tree is
  constant TB   : string := "tb_cell_tree";
  constant ID_BITS : positive := RAY_PACKET_CELL_TREE_NODE_WIDTH;
  constant LONGEST : positive := 2 * 2 ** ID_BITS + 8;  -- a walk of every slot, and more
  signal clk, rst, in_valid, in_ready, out_valid, frozen : std_logic := '0';
  signal node_in, node_out, rd_slot, rd_root : std_logic_vector(ID_BITS - 1 downto 0) := (others => '0');
  signal cell, rd_cell : std_logic_vector(RAY_PACKET_CELL_ID_WIDTH - 1 downto 0) := (others => '0');
  signal used : std_logic_vector(ID_BITS downto 0);
  signal rd_node : CELL_TREE_NODE_T;
begin
  dut : entity work.cell_tree
    port map (clk => clk, rst => rst, in_valid => in_valid, in_ready => in_ready,
              node_in => node_in, cell => cell, out_valid => out_valid, node_out => node_out,
              used => used, frozen => frozen, rd_slot => rd_slot, rd_cell => rd_cell,
              rd_node => rd_node, rd_root => rd_root);

  run : process
    file f, rf, tf : text;
    variable l : line;
    variable lineno, errs, lat, n, lat_min, lat_max : natural := 0;
    variable ok : boolean;
    variable i_node, e_node, e_root : std_logic_vector(ID_BITS - 1 downto 0);
    variable i_cell : std_logic_vector(cell'range);
    variable e_slot : CELL_TREE_NODE_T;
  begin
    open_vectors(f, VECTORS, TB);
    open_vectors(rf, RAM, TB);
    open_vectors(tf, ROOTS, TB);
    reset(clk, rst);
    while in_ready /= '1' loop  -- the root table's clearing
      tick(clk);
    end loop;
    lat_min := natural'high;
    while not endfile(f) loop
      next_line(f, l, lineno, ok);
      read_col(l, true, "node_in", lineno, i_node, ok, errs);
      read_col(l, false, "cell", lineno, i_cell, ok, errs);
      read_col(l, false, "node_out", lineno, e_node, ok, errs);
      end_of_line(l, lineno, ok, errs);
      next when not ok;
      node_in <= i_node;
      cell <= i_cell;
      in_valid <= '1';
      wait for HALF;
      check(lineno, "in_ready", "1", (0 => in_ready), errs);
      edge(clk);
      in_valid <= '0';
      await_out(clk, out_valid, LONGEST, lat);
      if out_valid /= '1' then
        report "line " & integer'image(lineno) & ": no out_valid within " &
          integer'image(lat) & " cycles" severity error;
        finish_run(TB, lineno, errs + 1);
      end if;
      check(lineno, "node_out", e_node, node_out, errs);
      lat_min := minimum(lat_min, lat);
      lat_max := maximum(lat_max, lat);
      edge(clk);
    end loop;
    tick(clk);  -- the last write-back
    -- the node RAM: slots 0..used-1
    n := 0;
    while not endfile(rf) loop
      next_line(rf, l, n, ok);
      read_col(l, true, "ram_final slot", n, e_slot, ok, errs);
      end_of_line(l, n, ok, errs);
      next when not ok;
      rd_slot <= std_logic_vector(to_unsigned(n - 1, ID_BITS));
      tick(clk);
      tick(clk);
      check(n, "ram_final slot " & integer'image(n - 1), e_slot, rd_node, errs);
    end loop;
    check(n, "used (the lines of " & RAM & ")", std_logic_vector(to_unsigned(n, used'length)),
          used, errs);
    -- the root table
    n := 0;
    while not endfile(tf) loop
      next_line(tf, l, n, ok);
      read_col(l, true, "root", n, e_root, ok, errs);
      end_of_line(l, n, ok, errs);
      exit when not ok or n > 2 ** RAY_PACKET_CELL_ID_WIDTH;
      rd_cell <= std_logic_vector(to_unsigned(n - 1, rd_cell'length));
      tick(clk);
      tick(clk);
      check(n, "roots_final cell " & integer'image(n - 1), e_root, rd_root, errs);
    end loop;
    if n /= 2 ** RAY_PACKET_CELL_ID_WIDTH then
      report ROOTS & ": " & integer'image(n) & " lines, " &
        integer'image(2 ** RAY_PACKET_CELL_ID_WIDTH) & " needed" severity error;
      errs := errs + 1;
    end if;
    if lineno > 0 then
      report TB & ": latency " & integer'image(lat_min) & " to " & integer'image(lat_max) &
        " cycles" severity note;
    end if;
    finish_run(TB, lineno, errs);
    wait;
  end process run;
end architecture sim;
