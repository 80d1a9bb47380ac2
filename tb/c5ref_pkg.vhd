-- The C model as a live reference (fpga/ref/, built into libc5ref.so) and the verdicts of
-- the `_live` testbenches: GHDL calls these functions through VHPIDIRECT, loading
-- ./libc5ref.so from the directory the simulation runs in (tests/live_test.sh copies it
-- there). VHDL wants a body for each; GHDL never runs it (ghdl -r stops with "cannot load
-- VHPIDIRECT shared library" when the library is missing), so every body is one call of
-- `unbound`, which stops the simulation should it ever run.
library ieee;
use ieee.std_logic_1164.all;
use std.env.all;

package c5ref_pkg is
  -- A std_logic as the integer the model uses for a flag: 1 for '1', else 0.
  function live_bit(b : std_logic) return integer;

  -- "TB: seed S WHAT": what a `_live` testbench's checks name before the step number N.
  function live_at(tb : string; seed : positive; what : string) return string;

  -- A `_live` testbench's check: a difference ends the run with
  -- "FAIL TB: seed S WHAT N: NAME: model X, VHDL Y" (at = live_at(TB, S, WHAT)) and exit
  -- status 1.
  procedure live_expect(at : string; n : natural; name : string; model, vhdl : integer);

  -- The end of a `_live` run that found no difference: "PASS TB: seed S, SUMMARY" and exit
  -- status 0.
  procedure live_pass(tb : string; seed : positive; summary : string);

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
  -- the datapath (fpga/ref/c5ref_interp.c, c5ref_gradient.c, c5ref_classify.c, c5ref_composite.c)
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

  function live_at(tb : string; seed : positive; what : string) return string is
  begin
    return tb & ": seed " & integer'image(seed) & " " & what;
  end function;

  procedure live_expect(at : string; n : natural; name : string; model, vhdl : integer) is
  begin
    if model /= vhdl then
      report "FAIL " & at & " " & integer'image(n) & ": " & name & ": model " & integer'image(model) &
        ", VHDL " & integer'image(vhdl) severity note;
      finish(1);
    end if;
  end procedure;

  procedure live_pass(tb : string; seed : positive; summary : string) is
  begin
    report "PASS " & tb & ": seed " & integer'image(seed) & ", " & summary severity note;
    finish(0);
  end procedure;

  -- The bodies VHDL requires of the foreign functions: never run under GHDL (see the header).
  impure function unbound(name : string) return integer is
  begin
    report name & ": libc5ref.so not bound" severity failure;
    return 0;
  end function;

  impure function c5ref_rq_reset(capacity, key_bits : integer) return integer is
    begin return unbound("c5ref_rq_reset"); end;
  impure function c5ref_rq_step(insert_valid, insert_key, insert_payload, pop_ready : integer)
    return integer is
    begin return unbound("c5ref_rq_step"); end;
  impure function c5ref_rq_out(k : integer) return integer is
    begin return unbound("c5ref_rq_out"); end;
  impure function c5ref_pk_set(i, word : integer) return integer is
    begin return unbound("c5ref_pk_set"); end;
  impure function c5ref_pk_run return integer is
    begin return unbound("c5ref_pk_run"); end;
  impure function c5ref_pk_field(k : integer) return integer is
    begin return unbound("c5ref_pk_field"); end;
  impure function c5ref_pk_word(i : integer) return integer is
    begin return unbound("c5ref_pk_word"); end;
  impure function c5ref_interp(fx, fy, fz, v0, v1, v2, v3, v4, v5, v6, v7 : integer) return integer is
    begin return unbound("c5ref_interp"); end;
  impure function c5ref_gr_set(k, v : integer) return integer is
    begin return unbound("c5ref_gr_set"); end;
  impure function c5ref_gr_run(axis : integer) return integer is
    begin return unbound("c5ref_gr_run"); end;
  impure function c5ref_cl_table(i, ch, v : integer) return integer is
    begin return unbound("c5ref_cl_table"); end;
  impure function c5ref_cl_run(value, ch : integer) return integer is
    begin return unbound("c5ref_cl_run"); end;
  impure function c5ref_tr_set(k, v : integer) return integer is
    begin return unbound("c5ref_tr_set"); end;
  impure function c5ref_tr_run return integer is
    begin return unbound("c5ref_tr_run"); end;
  impure function c5ref_tr_out(k : integer) return integer is
    begin return unbound("c5ref_tr_out"); end;
  impure function c5ref_ct_reset(capacity : integer) return integer is
    begin return unbound("c5ref_ct_reset"); end;
  impure function c5ref_ct_tag(node, cell : integer) return integer is
    begin return unbound("c5ref_ct_tag"); end;
  impure function c5ref_ct_state(k : integer) return integer is
    begin return unbound("c5ref_ct_state"); end;
  impure function c5ref_ct_slot_word(slot, i : integer) return integer is
    begin return unbound("c5ref_ct_slot_word"); end;
  impure function c5ref_ct_root(cell : integer) return integer is
    begin return unbound("c5ref_ct_root"); end;
  impure function c5ref_sh_setup(seed : integer) return integer is
    begin return unbound("c5ref_sh_setup"); end;
  impure function c5ref_sh_reg(addr : integer) return integer is
    begin return unbound("c5ref_sh_reg"); end;
  impure function c5ref_sh_pow(i : integer) return integer is
    begin return unbound("c5ref_sh_pow"); end;
  impure function c5ref_sh_dir(x, y, z, a : integer) return integer is
    begin return unbound("c5ref_sh_dir"); end;
  impure function c5ref_sh_set(k, v : integer) return integer is
    begin return unbound("c5ref_sh_set"); end;
  impure function c5ref_sh_run(k : integer) return integer is
    begin return unbound("c5ref_sh_run"); end;
  impure function c5ref_cp_set(k, v : integer) return integer is
    begin return unbound("c5ref_cp_set"); end;
  impure function c5ref_cp_run return integer is
    begin return unbound("c5ref_cp_run"); end;
  impure function c5ref_cp_out(k : integer) return integer is
    begin return unbound("c5ref_cp_out"); end;
end package body c5ref_pkg;
