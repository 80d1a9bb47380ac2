-- tb_packet_live: packet (fpga/rtl/packet.vhd, combinational)
-- against the C model's codec running beside it (c5ref_pk_*, generated from the same
-- spec/layouts.toml; docs/vectors.md, "The model inside the simulator").
--
-- Drives:  PACKETS 256-bit packets drawn from SEED alone (random words, all zeros, all ones,
--          a single one) into packet_in and the model; then the DUT's fields into fields_in.
-- Checks:  1 ns after each, every unpacked field, then the packed packet (reserved bits
--          packed as 0 on both sides) = the model's; the first difference ends the run:
--          "FAIL tb_packet_live: seed S packet N: FIELD: model X, VHDL Y".
-- Latency: none (combinational).
-- Usage:   ghdl -r --std=08 tb_packet_live -gSEED=1 -gPACKETS=2000 (./libc5ref.so beside)
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use work.c5_layouts_pkg.all;
use work.c5ref_pkg.all;
use work.tb_pkg.all;

entity tb_packet_live is
  generic (SEED : positive := 1; PACKETS : positive := 2000);
end entity tb_packet_live;

architecture sim of tb_packet_live is
  constant TB : string := "tb_packet_live";
  constant AT : string := live_at(TB, SEED, "packet");
  signal fields_in, fields_out : ray_packet_rec;
  signal packet_in, packet_out : RAY_PACKET_T;
begin
  dut : entity work.packet
    port map (fields_in => fields_in, packet_out => packet_out, packet_in => packet_in, fields_out => fields_out);

  run : process
    variable rnd : random_t;
    variable pk : RAY_PACKET_T;
    variable rc : integer;

    -- field k of the model against a DUT field (signed fields as negative numbers)
    procedure field(n, k : natural; name : string; v : std_logic_vector; sgn : boolean) is
    begin
      if sgn then
        live_expect(AT, n, name, c5ref_pk_field(k), to_integer(signed(v)));
      else
        live_expect(AT, n, name, c5ref_pk_field(k), to_integer(unsigned(v)));
      end if;
    end procedure;
  begin
    rnd.seed(SEED);
    for n in 0 to PACKETS - 1 loop
      case n mod 16 is
        when 0 => pk := (others => '0');
        when 1 => pk := (others => '1');
        when 2 =>
          pk := (others => '0');
          pk(rnd.pick(256)) := '1';
        when others =>
          for w in 0 to 15 loop
            pk(16 * w + 15 downto 16 * w) := std_logic_vector(to_unsigned(rnd.pick(65536), 16));
          end loop;
      end case;
      packet_in <= pk;
      for i in 0 to 7 loop
        rc := c5ref_pk_set(i, to_integer(signed(pk(32 * i + 31 downto 32 * i))));
      end loop;
      rc := c5ref_pk_run;
      wait for 1 ns;
      -- the layout's fields in order, MSB first (C5_RAY_PACKET_FIELDS)
      field(n, 0, "pos_x", fields_out.pos_x, false);
      field(n, 1, "pos_y", fields_out.pos_y, false);
      field(n, 2, "pos_z", fields_out.pos_z, false);
      field(n, 3, "dir_x", fields_out.dir_x, true);
      field(n, 4, "dir_y", fields_out.dir_y, true);
      field(n, 5, "dir_z", fields_out.dir_z, true);
      field(n, 6, "dest_u", fields_out.dest_u, false);
      field(n, 7, "dest_v", fields_out.dest_v, false);
      field(n, 8, "lifetime", fields_out.lifetime, false);
      field(n, 9, "contribution", fields_out.contribution, false);
      field(n, 10, "opacity", fields_out.opacity, false);
      field(n, 11, "generation", fields_out.generation, false);
      field(n, 12, "cell_tree_node", fields_out.cell_tree_node, false);
      field(n, 13, "cell_id", fields_out.cell_id, false);
      field(n, 14, "red", fields_out.red, false);
      field(n, 15, "type", fields_out.type_f, false);
      field(n, 16, "green", fields_out.green, false);
      field(n, 17, "blue", fields_out.blue, false);
      field(n, 18, "interaction", fields_out.interaction, false);
      fields_in <= fields_out;
      wait for 1 ns;
      for i in 0 to 7 loop
        live_expect(AT, n, "packet word " & integer'image(i), c5ref_pk_word(i),
               to_integer(signed(packet_out(32 * i + 31 downto 32 * i))));
      end loop;
    end loop;
    live_pass(TB, SEED, integer'image(PACKETS) & " packets");
  end process run;
end architecture sim;
