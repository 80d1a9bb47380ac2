-- The C model as a live reference (fpga/ref/, built into libc5ref.so): GHDL calls these
-- functions through VHPIDIRECT, loading ./libc5ref.so from the directory the simulation
-- runs in (tests/live_test.sh copies it there). Each body only runs when the library could
-- not be bound, and then stops the simulation.
package c5ref_pkg is
  impure function c5ref_rq_reset(capacity, key_bits : integer) return integer;
  attribute foreign of c5ref_rq_reset : function is "VHPIDIRECT ./libc5ref.so c5ref_rq_reset";
  impure function c5ref_rq_step(insert_valid, insert_key, insert_payload, pop_ready : integer)
    return integer;
  attribute foreign of c5ref_rq_step : function is "VHPIDIRECT ./libc5ref.so c5ref_rq_step";
  impure function c5ref_rq_out(k : integer) return integer;
  attribute foreign of c5ref_rq_out : function is "VHPIDIRECT ./libc5ref.so c5ref_rq_out";
end package c5ref_pkg;

package body c5ref_pkg is
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
end package body c5ref_pkg;
