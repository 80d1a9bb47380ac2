-- Reading golden vector files and reporting mismatches, shared by the testbenches.
--
-- The format (written by `cube5 vectors`, described in fpga/README.md): one vector per
-- line, the columns in a fixed order separated by exactly one space, each column exactly
-- ceil(width / 4) lowercase hex digits, zero-padded (signed values in two's complement
-- masked to their width), no header, no comments. The column widths are taken from the
-- vectors read into (generated record members, DUT ports), never written here.
--
-- Every problem is counted in `errs`; the first MAX_REPORTS are reported with the line
-- number (= vector index, from 1), the column name, the expected and the obtained value.
library ieee;
use ieee.std_logic_1164.all;
use ieee.std_logic_textio.all;  -- hread (part of std_logic_1164 in VHDL-2008)
use std.textio.all;

package vec_io_pkg is
  constant MAX_REPORTS : positive := 10;

  -- Opens `path` for reading; a file that cannot be opened ends the run with FAIL.
  procedure open_vectors(file f : text; path : string; tb : string);

  -- Reads the next line of f into l: ok = false at the end of the file (nothing read), else
  -- lineno counts the line and ok = true until a column of it is found malformed.
  procedure next_line(file f : text; l : inout line; lineno : inout natural; ok : out boolean);

  -- Reads the next column of line `l` into v (v'length bits): one separating space unless
  -- `first`, then exactly ceil(v'length / 4) hex digits whose padding bits are 0. A
  -- malformed column is one error and clears `ok`; with `ok` false already, nothing is
  -- read (the rest of a malformed line would only repeat the error), and the caller skips
  -- the line's comparisons.
  procedure read_col(l : inout line; first : boolean; name : string; lineno : positive;
                     v : out std_logic_vector; ok : inout boolean; errs : inout natural);

  -- Whatever is left on the line after the last column is an error (clears `ok`).
  procedure end_of_line(l : inout line; lineno : positive; ok : inout boolean;
                        errs : inout natural);

  -- Counts (and reports, the first MAX_REPORTS times) expected /= got.
  procedure check(lineno : positive; name : string; expected, got : std_logic_vector;
                  errs : inout natural);

  -- A pipelined testbench's cycle, once its outputs have settled: from the cycle `full`
  -- (LAT cycles after the first vector) on, out_valid must equal the `valid` of the vector
  -- driven LAT cycles before (line lineno); `due` says whether that vector's outputs are
  -- to be compared now.
  procedure check_valid(full : boolean; lineno : positive; valid : boolean; out_valid : std_logic;
                        errs : inout natural; due : out boolean);

  -- A boolean as a 1-bit vector, for check on single-bit ports: bits(b) = "1" or "0".
  function bits(b : boolean) return std_logic_vector;

  -- The verdict, a plain line on standard output: "PASS tb: N vectors" or "FAIL tb: E
  -- error(s) in N vectors" (or "FAIL tb: no vectors"), then std.env.finish with status 0
  -- on PASS and 1 on FAIL, which ghdl -r returns as its exit status.
  procedure finish_run(tb : string; vectors : natural; errs : natural);
end package vec_io_pkg;

package body vec_io_pkg is
  -- A plain line on standard output (no report prefix): the verdict scripts look for.
  procedure say(msg : string) is
    variable l : line;
  begin
    write(l, msg);
    writeline(output, l);
  end procedure say;

  procedure problem(lineno : positive; msg : string; errs : inout natural) is
  begin
    errs := errs + 1;
    if errs <= MAX_REPORTS then
      report "line " & integer'image(lineno) & ": " & msg severity error;
    elsif errs = MAX_REPORTS + 1 then
      report "further errors not reported" severity error;
    end if;
  end procedure problem;

  -- Hex as the vector files write it (to_hstring writes upper case; 'X' for metavalues).
  function lower_hex(v : std_logic_vector) return string is
    variable s : string(1 to (v'length + 3) / 4) := to_hstring(v);
  begin
    for i in s'range loop
      if s(i) >= 'A' and s(i) <= 'F' then
        s(i) := character'val(character'pos(s(i)) + 32);
      end if;
    end loop;
    return s;
  end function lower_hex;

  procedure open_vectors(file f : text; path : string; tb : string) is
    variable status : file_open_status;
  begin
    file_open(status, f, path, read_mode);
    if status /= open_ok then
      say("FAIL " & tb & ": cannot open " & path & " (" & file_open_status'image(status) & ")");
      std.env.finish(1);
    end if;
  end procedure open_vectors;

  procedure next_line(file f : text; l : inout line; lineno : inout natural; ok : out boolean) is
  begin
    ok := not endfile(f);
    if not endfile(f) then
      readline(f, l);
      lineno := lineno + 1;
    end if;
  end procedure next_line;

  procedure read_col(l : inout line; first : boolean; name : string; lineno : positive;
                     v : out std_logic_vector; ok : inout boolean; errs : inout natural) is
    constant DIGITS : positive := (v'length + 3) / 4;
    variable hex : std_logic_vector(4 * DIGITS - 1 downto 0);
    variable sep : character;
    variable good : boolean;
  begin
    v := (v'range => 'X');
    if not ok then
      return;
    end if;
    ok := false;  -- until the column is read
    if l = null or l'length = 0 then
      problem(lineno, name & ": missing column", errs);
      return;
    end if;
    if not first then
      read(l, sep, good);
      if not good or sep /= ' ' or l'length = 0 or l(l'left) = ' ' then
        problem(lineno, name & ": columns must be separated by exactly one space", errs);
        return;
      end if;
    end if;
    if l'length < DIGITS then
      problem(lineno, name & ": expected " & integer'image(DIGITS) & " hex digits", errs);
      return;
    end if;
    for i in l'left to l'left + DIGITS - 1 loop  -- hread also takes '_' and upper case
      if not ((l(i) >= '0' and l(i) <= '9') or (l(i) >= 'a' and l(i) <= 'f')) then
        problem(lineno, name & ": expected " & integer'image(DIGITS) &
                " lowercase hex digits, found '" & l(i) & "'", errs);
        return;
      end if;
    end loop;
    hread(l, hex, good);
    if not good then
      problem(lineno, name & ": unreadable hex", errs);
      return;
    end if;
    if hex'length > v'length and hex(hex'left downto v'length) /= (hex'left downto v'length => '0') then
      problem(lineno, name & ": " & lower_hex(hex) & " does not fit " &
              integer'image(v'length) & " bits", errs);
      return;
    end if;
    v := hex(v'length - 1 downto 0);
    ok := true;
  end procedure read_col;

  procedure end_of_line(l : inout line; lineno : positive; ok : inout boolean;
                        errs : inout natural) is
  begin
    if ok and l /= null and l'length /= 0 then
      ok := false;
      problem(lineno, "unexpected text after the last column: '" & l.all & "'", errs);
    end if;
  end procedure end_of_line;

  procedure check(lineno : positive; name : string; expected, got : std_logic_vector;
                  errs : inout natural) is
  begin
    if got /= expected then
      problem(lineno, name & ": expected " & lower_hex(expected) & " got " & lower_hex(got), errs);
    end if;
  end procedure check;

  procedure check_valid(full : boolean; lineno : positive; valid : boolean; out_valid : std_logic;
                        errs : inout natural; due : out boolean) is
  begin
    due := full and valid;
    if full then
      check(lineno, "out_valid", bits(valid), (0 => out_valid), errs);
    end if;
  end procedure check_valid;

  function bits(b : boolean) return std_logic_vector is
  begin
    if b then
      return "1";
    end if;
    return "0";
  end function bits;

  procedure finish_run(tb : string; vectors : natural; errs : natural) is
  begin
    if vectors = 0 then
      say("FAIL " & tb & ": no vectors");
      std.env.finish(1);
    elsif errs = 0 then
      say("PASS " & tb & ": " & integer'image(vectors) & " vectors");
      std.env.finish(0);
    else
      if errs = 1 then
        say("FAIL " & tb & ": 1 error in " & integer'image(vectors) & " vectors");
      else
        say("FAIL " & tb & ": " & integer'image(errs) & " errors in " &
            integer'image(vectors) & " vectors");
      end if;
      std.env.finish(1);
    end if;
  end procedure finish_run;
end package body vec_io_pkg;
