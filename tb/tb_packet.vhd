-- tb_packet: packet (fpga/rtl/packet.vhd, combinational)
-- against the golden vectors packet.*.hex.
--
-- Drives:  each line's fields into fields_in and its packet into packet_in: pos_x pos_y
--          pos_z dir_x dir_y dir_z dest_u dest_v lifetime contribution opacity generation
--          cell_tree_node cell_id red type green blue interaction (the layout's fields MSB
--          first, reserved ones left out; widths of the generated record members,
--          spec/layouts.toml), then packet (the 256-bit packet as one number, MSB first,
--          bit i of the layout = bit i of the number).
-- Checks:  1 ns later, pack(fields) = packet and unpack(packet) = every field; a malformed
--          line is one error and is skipped.
-- Latency: none (combinational).
-- Usage:   ghdl -r --std=08 tb_packet -gVECTORS=path/packet.x.hex
library ieee;
use ieee.std_logic_1164.all;
use std.textio.all;
use work.c5_layouts_pkg.all;
use work.vec_io_pkg.all;

entity tb_packet is
  generic (VECTORS : string := "packet.hex");
end entity tb_packet;

architecture sim of tb_packet is
  constant TB : string := "tb_packet";
  signal fields_in, fields_out : ray_packet_rec;
  signal packet_in, packet_out : RAY_PACKET_T;
begin
  dut : entity work.packet
    port map (fields_in => fields_in, packet_out => packet_out,
              packet_in => packet_in, fields_out => fields_out);

  run : process
    file f : text;
    variable l : line;
    variable lineno, errs : natural := 0;
    variable ok : boolean;     -- the line is well formed
    variable r : ray_packet_rec;  -- the fields column by column
    variable p : RAY_PACKET_T;    -- the packet column
  begin
    open_vectors(f, VECTORS, TB);
    while not endfile(f) loop
      next_line(f, l, lineno, ok);
      read_col(l, true,  "pos_x", lineno, r.pos_x, ok, errs);
      read_col(l, false, "pos_y", lineno, r.pos_y, ok, errs);
      read_col(l, false, "pos_z", lineno, r.pos_z, ok, errs);
      read_col(l, false, "dir_x", lineno, r.dir_x, ok, errs);
      read_col(l, false, "dir_y", lineno, r.dir_y, ok, errs);
      read_col(l, false, "dir_z", lineno, r.dir_z, ok, errs);
      read_col(l, false, "dest_u", lineno, r.dest_u, ok, errs);
      read_col(l, false, "dest_v", lineno, r.dest_v, ok, errs);
      read_col(l, false, "lifetime", lineno, r.lifetime, ok, errs);
      read_col(l, false, "contribution", lineno, r.contribution, ok, errs);
      read_col(l, false, "opacity", lineno, r.opacity, ok, errs);
      read_col(l, false, "generation", lineno, r.generation, ok, errs);
      read_col(l, false, "cell_tree_node", lineno, r.cell_tree_node, ok, errs);
      read_col(l, false, "cell_id", lineno, r.cell_id, ok, errs);
      read_col(l, false, "red", lineno, r.red, ok, errs);
      read_col(l, false, "type", lineno, r.type_f, ok, errs);
      read_col(l, false, "green", lineno, r.green, ok, errs);
      read_col(l, false, "blue", lineno, r.blue, ok, errs);
      read_col(l, false, "interaction", lineno, r.interaction, ok, errs);
      read_col(l, false, "packet", lineno, p, ok, errs);
      end_of_line(l, lineno, ok, errs);
      next when not ok;  -- a malformed line is one error; nothing to compare

      fields_in <= r;
      packet_in <= p;
      wait for 1 ns;

      -- fields -> packet
      check(lineno, "packet (pack of the fields)", p, packet_out, errs);
      -- packet -> fields
      check(lineno, "pos_x", r.pos_x, fields_out.pos_x, errs);
      check(lineno, "pos_y", r.pos_y, fields_out.pos_y, errs);
      check(lineno, "pos_z", r.pos_z, fields_out.pos_z, errs);
      check(lineno, "dir_x", r.dir_x, fields_out.dir_x, errs);
      check(lineno, "dir_y", r.dir_y, fields_out.dir_y, errs);
      check(lineno, "dir_z", r.dir_z, fields_out.dir_z, errs);
      check(lineno, "dest_u", r.dest_u, fields_out.dest_u, errs);
      check(lineno, "dest_v", r.dest_v, fields_out.dest_v, errs);
      check(lineno, "lifetime", r.lifetime, fields_out.lifetime, errs);
      check(lineno, "contribution", r.contribution, fields_out.contribution, errs);
      check(lineno, "opacity", r.opacity, fields_out.opacity, errs);
      check(lineno, "generation", r.generation, fields_out.generation, errs);
      check(lineno, "cell_tree_node", r.cell_tree_node, fields_out.cell_tree_node, errs);
      check(lineno, "cell_id", r.cell_id, fields_out.cell_id, errs);
      check(lineno, "red", r.red, fields_out.red, errs);
      check(lineno, "type", r.type_f, fields_out.type_f, errs);
      check(lineno, "green", r.green, fields_out.green, errs);
      check(lineno, "blue", r.blue, fields_out.blue, errs);
      check(lineno, "interaction", r.interaction, fields_out.interaction, errs);
    end loop;
    finish_run(TB, lineno, errs);
    wait;
  end process run;
end architecture sim;
