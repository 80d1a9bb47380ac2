-- The ray packet codec: fields -> the 256-bit packet, and the packet -> fields.
--
-- Pure combinational wiring through the generated ray_packet_pack / ray_packet_unpack
-- (build/gen/c5_layouts_pkg.vhd, from spec/layouts.toml): no field position is written in
-- this file, so the codec cannot drift from the C model's c5_ray_packet_pack/unpack.
-- Reserved bits are packed as 0 and ignored when unpacking. The two directions are
-- independent ports so one instance can serve a queue's write and read side at once.
-- No registers: a caller that needs a pipeline stage puts it around the codec, where its
-- timing is known (packing is only wires, so a register here would buy nothing).
library ieee;
use ieee.std_logic_1164.all;

library work;
use work.c5_layouts_pkg.all;

entity packet is
  port (
    fields_in  : in  ray_packet_rec;   -- to be packed
    packet_out : out RAY_PACKET_T;     -- ray_packet_pack(fields_in)
    packet_in  : in  RAY_PACKET_T;     -- to be unpacked
    fields_out : out ray_packet_rec);  -- ray_packet_unpack(packet_in)
end entity packet;

architecture rtl of packet is
begin
  packet_out <= ray_packet_pack(fields_in);
  fields_out <= ray_packet_unpack(packet_in);
end architecture rtl;
