-- File-driven testbench of cell_tree against cell_tree.*.hex: from the empty tree (reset,
-- then the root table's clearing), one tag at a time: node_in and cell driven with
-- in_valid while in_ready = 1, node_out compared when out_valid comes; then the final
-- images through the readback ports: `used` must be the number of lines of
-- cell_tree.SOURCE.ram_final.hex (slots 0..used-1, 96 bits a line) and every slot equal
-- its line, and every root equal its line of cell_tree.SOURCE.roots_final.hex (line c =
-- cell c). Reports the latencies seen (cell_tree.vhd has the formula). A malformed line
-- is one error and skipped; a missing out_valid ends the run. Usage:
--   ghdl -r --std=08 tb_cell_tree -gVECTORS=cell_tree.x.hex -gRAM=cell_tree.x.ram_final.hex
--        -gROOTS=cell_tree.x.roots_final.hex
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use std.textio.all;

library work;
use work.c5_layouts_pkg.all;
use work.vec_io_pkg.all;

entity tb_cell_tree is
  generic (VECTORS : string := "cell_tree.hex"; RAM : string := "cell_tree.ram_final.hex";
           ROOTS : string := "cell_tree.roots_final.hex");
end entity tb_cell_tree;

architecture sim of tb_cell_tree is
  constant TB   : string := "tb_cell_tree";
  constant HALF : time := 5 ns;
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

    procedure tick is
    begin
      wait for HALF;
      clk <= '1';
      wait for HALF;
      clk <= '0';
    end procedure tick;
  begin
    open_vectors(f, VECTORS, TB);
    open_vectors(rf, RAM, TB);
    open_vectors(tf, ROOTS, TB);
    rst <= '1';
    tick;
    rst <= '0';
    while in_ready /= '1' loop  -- the root table's clearing
      tick;
    end loop;
    lat_min := natural'high;
    while not endfile(f) loop
      readline(f, l);
      lineno := lineno + 1;
      ok := true;
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
      clk <= '1';
      wait for HALF;
      clk <= '0';
      in_valid <= '0';
      lat := 0;
      loop
        lat := lat + 1;
        wait for HALF;
        exit when out_valid = '1';
        if lat > LONGEST then
          report "line " & integer'image(lineno) & ": no out_valid within " &
            integer'image(lat) & " cycles" severity error;
          finish_run(TB, lineno, errs + 1);
        end if;
        clk <= '1';
        wait for HALF;
        clk <= '0';
      end loop;
      check(lineno, "node_out", e_node, node_out, errs);
      lat_min := minimum(lat_min, lat);
      lat_max := maximum(lat_max, lat);
      clk <= '1';
      wait for HALF;
      clk <= '0';
    end loop;
    tick;  -- the last write-back
    -- the node RAM: slots 0..used-1
    n := 0;
    while not endfile(rf) loop
      readline(rf, l);
      n := n + 1;
      ok := true;
      read_col(l, true, "ram_final slot", n, e_slot, ok, errs);
      end_of_line(l, n, ok, errs);
      next when not ok;
      rd_slot <= std_logic_vector(to_unsigned(n - 1, ID_BITS));
      tick;
      tick;
      check(n, "ram_final slot " & integer'image(n - 1), e_slot, rd_node, errs);
    end loop;
    check(n, "used (the lines of " & RAM & ")", std_logic_vector(to_unsigned(n, used'length)),
          used, errs);
    -- the root table
    n := 0;
    while not endfile(tf) loop
      readline(tf, l);
      n := n + 1;
      ok := true;
      read_col(l, true, "root", n, e_root, ok, errs);
      end_of_line(l, n, ok, errs);
      exit when not ok or n > 2 ** RAY_PACKET_CELL_ID_WIDTH;
      rd_cell <= std_logic_vector(to_unsigned(n - 1, rd_cell'length));
      tick;
      tick;
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
