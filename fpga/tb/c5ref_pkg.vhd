-- The C model as a live reference (fpga/ref/, built into libc5ref.so): GHDL calls these
-- functions through VHPIDIRECT, loading ./libc5ref.so from the directory the simulation
-- runs in (tests/live_test.sh copies it there). Each body only runs when the library could
-- not be bound, and then stops the simulation.
library ieee;
use ieee.std_logic_1164.all;
use std.env.all;

package c5ref_pkg is
  -- A std_logic as the integer the model uses for a flag: 1 for '1', else 0.
  function live_bit(b : std_logic) return integer;

  -- A `_live` testbench's check: a difference ends the run with
  -- "FAIL TB: seed S WHAT N: NAME: model X, VHDL Y" and exit status 1.
  procedure live_expect(tb : string; seed : positive; what : string; n : natural; name : string;
                        model, vhdl : integer);

  impure function c5ref_rq_reset(capacity, key_bits : integer) return integer;
  attribute foreign of c5ref_rq_reset : function is "VHPIDIRECT ./libc5ref.so c5ref_rq_reset";
  impure function c5ref_rq_step(insert_valid, insert_key, insert_payload, pop_ready : integer)
    return integer;
  attribute foreign of c5ref_rq_step : function is "VHPIDIRECT ./libc5ref.so c5ref_rq_step";
  impure function c5ref_rq_out(k : integer) return integer;
  attribute foreign of c5ref_rq_out : function is "VHPIDIRECT ./libc5ref.so c5ref_rq_out";
  -- the ray packet codec (fpga/ref/c5ref_packet.c)
  impure function c5ref_pk_set(i, word : integer) return integer;
  attribute foreign of c5ref_pk_set : function is "VHPIDIRECT ./libc5ref.so c5ref_pk_set";
  impure function c5ref_pk_run return integer;
  attribute foreign of c5ref_pk_run : function is "VHPIDIRECT ./libc5ref.so c5ref_pk_run";
  impure function c5ref_pk_field(k : integer) return integer;
  attribute foreign of c5ref_pk_field : function is "VHPIDIRECT ./libc5ref.so c5ref_pk_field";
  impure function c5ref_pk_word(i : integer) return integer;
  attribute foreign of c5ref_pk_word : function is "VHPIDIRECT ./libc5ref.so c5ref_pk_word";
  -- the datapath (fpga/ref/c5ref_datapath.c)
  impure function c5ref_interp(fx, fy, fz, v0, v1, v2, v3, v4, v5, v6, v7 : integer) return integer;
  attribute foreign of c5ref_interp : function is "VHPIDIRECT ./libc5ref.so c5ref_interp";
  impure function c5ref_gr_set(k, v : integer) return integer;
  attribute foreign of c5ref_gr_set : function is "VHPIDIRECT ./libc5ref.so c5ref_gr_set";
  impure function c5ref_gr_run(axis : integer) return integer;
  attribute foreign of c5ref_gr_run : function is "VHPIDIRECT ./libc5ref.so c5ref_gr_run";
  impure function c5ref_cl_table(i, ch, v : integer) return integer;
  attribute foreign of c5ref_cl_table : function is "VHPIDIRECT ./libc5ref.so c5ref_cl_table";
  impure function c5ref_cl_run(value, ch : integer) return integer;
  attribute foreign of c5ref_cl_run : function is "VHPIDIRECT ./libc5ref.so c5ref_cl_run";
  impure function c5ref_tr_set(k, v : integer) return integer;
  attribute foreign of c5ref_tr_set : function is "VHPIDIRECT ./libc5ref.so c5ref_tr_set";
  impure function c5ref_tr_run return integer;
  attribute foreign of c5ref_tr_run : function is "VHPIDIRECT ./libc5ref.so c5ref_tr_run";
  impure function c5ref_tr_out(k : integer) return integer;
  attribute foreign of c5ref_tr_out : function is "VHPIDIRECT ./libc5ref.so c5ref_tr_out";
  impure function c5ref_ct_reset(capacity : integer) return integer;
  attribute foreign of c5ref_ct_reset : function is "VHPIDIRECT ./libc5ref.so c5ref_ct_reset";
  impure function c5ref_ct_tag(node, cell : integer) return integer;
  attribute foreign of c5ref_ct_tag : function is "VHPIDIRECT ./libc5ref.so c5ref_ct_tag";
  impure function c5ref_ct_state(k : integer) return integer;
  attribute foreign of c5ref_ct_state : function is "VHPIDIRECT ./libc5ref.so c5ref_ct_state";
  impure function c5ref_ct_slot_word(slot, i : integer) return integer;
  attribute foreign of c5ref_ct_slot_word : function is "VHPIDIRECT ./libc5ref.so c5ref_ct_slot_word";
  impure function c5ref_ct_root(cell : integer) return integer;
  attribute foreign of c5ref_ct_root : function is "VHPIDIRECT ./libc5ref.so c5ref_ct_root";
  impure function c5ref_sh_setup(seed : integer) return integer;
  attribute foreign of c5ref_sh_setup : function is "VHPIDIRECT ./libc5ref.so c5ref_sh_setup";
  impure function c5ref_sh_reg(addr : integer) return integer;
  attribute foreign of c5ref_sh_reg : function is "VHPIDIRECT ./libc5ref.so c5ref_sh_reg";
  impure function c5ref_sh_pow(i : integer) return integer;
  attribute foreign of c5ref_sh_pow : function is "VHPIDIRECT ./libc5ref.so c5ref_sh_pow";
  impure function c5ref_sh_dir(x, y, z, a : integer) return integer;
  attribute foreign of c5ref_sh_dir : function is "VHPIDIRECT ./libc5ref.so c5ref_sh_dir";
  impure function c5ref_sh_set(k, v : integer) return integer;
  attribute foreign of c5ref_sh_set : function is "VHPIDIRECT ./libc5ref.so c5ref_sh_set";
  impure function c5ref_sh_run(k : integer) return integer;
  attribute foreign of c5ref_sh_run : function is "VHPIDIRECT ./libc5ref.so c5ref_sh_run";
  impure function c5ref_cp_set(k, v : integer) return integer;
  attribute foreign of c5ref_cp_set : function is "VHPIDIRECT ./libc5ref.so c5ref_cp_set";
  impure function c5ref_cp_run return integer;
  attribute foreign of c5ref_cp_run : function is "VHPIDIRECT ./libc5ref.so c5ref_cp_run";
  impure function c5ref_cp_out(k : integer) return integer;
  attribute foreign of c5ref_cp_out : function is "VHPIDIRECT ./libc5ref.so c5ref_cp_out";
end package c5ref_pkg;

package body c5ref_pkg is
  function live_bit(b : std_logic) return integer is
  begin
    if b = '1' then
      return 1;
    end if;
    return 0;
  end function;

  procedure live_expect(tb : string; seed : positive; what : string; n : natural; name : string;
                        model, vhdl : integer) is
  begin
    if model /= vhdl then
      report "FAIL " & tb & ": seed " & integer'image(seed) & " " & what & " " & integer'image(n) & ": " &
        name & ": model " & integer'image(model) & ", VHDL " & integer'image(vhdl) severity note;
      finish(1);
    end if;
  end procedure;

  impure function c5ref_rq_reset(capacity, key_bits : integer) return integer is
  begin
    report "c5ref_rq_reset: libc5ref.so not bound" severity failure;
    return -1;
  end function;
  impure function c5ref_rq_step(insert_valid, insert_key, insert_payload, pop_ready : integer)
    return integer is
  begin
    report "c5ref_rq_step: libc5ref.so not bound" severity failure;
    return -1;
  end function;
  impure function c5ref_rq_out(k : integer) return integer is
  begin
    report "c5ref_rq_out: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_pk_set(i, word : integer) return integer is
  begin
    report "c5ref_pk_set: libc5ref.so not bound" severity failure;
    return -1;
  end function;
  impure function c5ref_pk_run return integer is
  begin
    report "c5ref_pk_run: libc5ref.so not bound" severity failure;
    return -1;
  end function;
  impure function c5ref_pk_field(k : integer) return integer is
  begin
    report "c5ref_pk_field: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_pk_word(i : integer) return integer is
  begin
    report "c5ref_pk_word: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_interp(fx, fy, fz, v0, v1, v2, v3, v4, v5, v6, v7 : integer) return integer is
  begin
    report "c5ref_interp: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_gr_set(k, v : integer) return integer is
  begin
    report "c5ref_gr_set: libc5ref.so not bound" severity failure;
    return -1;
  end function;
  impure function c5ref_gr_run(axis : integer) return integer is
  begin
    report "c5ref_gr_run: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_cl_table(i, ch, v : integer) return integer is
  begin
    report "c5ref_cl_table: libc5ref.so not bound" severity failure;
    return -1;
  end function;
  impure function c5ref_cl_run(value, ch : integer) return integer is
  begin
    report "c5ref_cl_run: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_tr_set(k, v : integer) return integer is
  begin
    report "c5ref_tr_set: libc5ref.so not bound" severity failure;
    return -1;
  end function;
  impure function c5ref_tr_run return integer is
  begin
    report "c5ref_tr_run: libc5ref.so not bound" severity failure;
    return -1;
  end function;
  impure function c5ref_tr_out(k : integer) return integer is
  begin
    report "c5ref_tr_out: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_ct_reset(capacity : integer) return integer is
  begin
    report "c5ref_ct_reset: libc5ref.so not bound" severity failure;
    return -1;
  end function;
  impure function c5ref_ct_tag(node, cell : integer) return integer is
  begin
    report "c5ref_ct_tag: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_ct_state(k : integer) return integer is
  begin
    report "c5ref_ct_state: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_ct_slot_word(slot, i : integer) return integer is
  begin
    report "c5ref_ct_slot_word: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_ct_root(cell : integer) return integer is
  begin
    report "c5ref_ct_root: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_sh_setup(seed : integer) return integer is
  begin
    report "c5ref_sh_setup: libc5ref.so not bound" severity failure;
    return -1;
  end function;
  impure function c5ref_sh_reg(addr : integer) return integer is
  begin
    report "c5ref_sh_reg: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_sh_pow(i : integer) return integer is
  begin
    report "c5ref_sh_pow: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_sh_dir(x, y, z, a : integer) return integer is
  begin
    report "c5ref_sh_dir: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_sh_set(k, v : integer) return integer is
  begin
    report "c5ref_sh_set: libc5ref.so not bound" severity failure;
    return -1;
  end function;
  impure function c5ref_sh_run(k : integer) return integer is
  begin
    report "c5ref_sh_run: libc5ref.so not bound" severity failure;
    return 0;
  end function;
  impure function c5ref_cp_set(k, v : integer) return integer is
  begin
    report "c5ref_cp_set: libc5ref.so not bound" severity failure;
    return -1;
  end function;
  impure function c5ref_cp_run return integer is
  begin
    report "c5ref_cp_run: libc5ref.so not bound" severity failure;
    return -1;
  end function;
  impure function c5ref_cp_out(k : integer) return integer is
  begin
    report "c5ref_cp_out: libc5ref.so not bound" severity failure;
    return 0;
  end function;
end package body c5ref_pkg;
