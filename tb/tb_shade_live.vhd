-- tb_shade_live: shade (fpga/rtl/shade.vhd) against the C model running beside it (c5ref_sh_*,
-- the model's c5_shade; docs/vectors.md, "The model inside the simulator").
--
-- Drives:  after the reset edge, the registers and the specular power table the model draws
--          from SEED (c5ref_sh_setup: ka kd ks, 1 to 8 point or directional lights,
--          (i / 1024)^p) through the configuration ports; then SAMPLES samples drawn from SEED
--          (gradients from zero through the lights' fade to +-255, transfer-function
--          colours at 0, 1 or random, positions in the volume's first 256 voxels, unit
--          directions), one at a time with in_valid while in_ready = 1.
-- Checks:  when out_valid comes, rgb and sat = the model's; the first difference ends the
--          run: "FAIL tb_shade_live: seed S sample N: PORT: model X, VHDL Y".
-- Latency: variable (shade.vhd has the formula); out_valid within 4096 cycles.
-- Usage:   ghdl -r --std=08 tb_shade_live -gSEED=1 -gSAMPLES=1000 (./libc5ref.so beside)
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use work.c5_layouts_pkg.all;
use work.dp_pkg.all;
use work.c5ref_pkg.all;
use work.tb_pkg.all;

entity tb_shade_live is
  generic (SEED : positive := 1; SAMPLES : positive := 1000);
end entity tb_shade_live;

architecture sim of tb_shade_live is
  constant TB : string := "tb_shade_live";
  constant AT : string := live_at(TB, SEED, "sample");
  signal clk, rst, in_valid, in_ready, out_valid, reg_we, pow_we : std_logic := '0';
  signal reg_addr : std_logic_vector(6 downto 0) := (others => '0');
  signal reg_data : std_logic_vector(31 downto 0) := (others => '0');
  signal pow_addr : std_logic_vector(POW_ADDR_BITS - 1 downto 0) := (others => '0');
  signal pow_data : std_logic_vector(SIG_SPEC_POW_WIDTH - 1 downto 0) := (others => '0');
  signal grad : grad3_t := (others => (others => '0'));
  signal tf : tf3_t := (others => (others => '0'));
  signal gpos : gpos3_t := (others => (others => '0'));
  signal dir : dir3_t := (others => (others => '0'));
  signal rgb : shaded3_t;
  signal sat : std_logic_vector(2 downto 0);
begin
  dut : entity work.shade
    port map (clk => clk, rst => rst, reg_we => reg_we, reg_addr => reg_addr, reg_data => reg_data,
              pow_we => pow_we, pow_addr => pow_addr, pow_data => pow_data, in_valid => in_valid,
              in_ready => in_ready, grad => grad, tf => tf, gpos => gpos, dir => dir, out_valid => out_valid,
              rgb => rgb, sat => sat);

  run : process
    constant ONE : integer := 2 ** SIG_TF_RGBA_FRAC;
    constant GMAX : integer := 65280;  -- 255.0 in SQ8.8
    variable rnd : random_t;
    variable x, rc, waited : integer;
    variable dv : integer_vector(0 to 2);
  begin
    rnd.seed(SEED);
    rc := c5ref_sh_setup(SEED);
    reset(clk, rst);
    for a in 0 to SHADE_REGS - 1 loop
      reg_we <= '1';
      reg_addr <= std_logic_vector(to_unsigned(a, reg_addr'length));
      reg_data <= std_logic_vector(to_signed(c5ref_sh_reg(a), 32));
      tick(clk);
    end loop;
    reg_we <= '0';
    for i in 0 to 2 ** POW_TABLE_BITS loop
      pow_we <= '1';
      pow_addr <= std_logic_vector(to_unsigned(i, POW_ADDR_BITS));
      pow_data <= std_logic_vector(to_unsigned(c5ref_sh_pow(i), SIG_SPEC_POW_WIDTH));
      tick(clk);
    end loop;
    pow_we <= '0';
    for n in 0 to SAMPLES - 1 loop
      for a in 0 to 2 loop
        case rnd.pick(6) is
          when 0 => x := 0;
          when 1 => x := rnd.pick(256) - 128;        -- the lights' fade (|g| < 1/2)
          when 2 => x := GMAX;
          when 3 => x := -GMAX;
          when others => x := rnd.pick(2 * GMAX + 1) - GMAX;
        end case;
        grad(a) <= std_logic_vector(to_signed(x, SIG_GRADIENT_WIDTH));
        rc := c5ref_sh_set(a, x);
        case rnd.pick(4) is
          when 0 => x := 0;
          when 1 => x := ONE;
          when others => x := rnd.pick(ONE + 1);
        end case;
        tf(a) <= std_logic_vector(to_unsigned(x, SIG_TF_RGBA_WIDTH));
        rc := c5ref_sh_set(3 + a, x);
        x := rnd.pick(256 * 2 ** 15);
        gpos(a) <= std_logic_vector(to_signed(x, SIG_GEOM_COORD_WIDTH));
        rc := c5ref_sh_set(6 + a, x);
        dv(a) := rnd.pick(65536) - 32768;
      end loop;
      for a in 0 to 2 loop
        x := c5ref_sh_dir(dv(0), dv(1), dv(2), a);
        dir(a) <= std_logic_vector(to_signed(x, RAY_PACKET_DIR_X_WIDTH));
        rc := c5ref_sh_set(9 + a, x);
      end loop;
      rc := c5ref_sh_run(-1);
      in_valid <= '1';
      wait for HALF;
      live_expect(AT, n, "in_ready", 1, live_bit(in_ready));
      edge(clk);
      in_valid <= '0';
      await_out(clk, out_valid, 4096, waited);
      live_expect(AT, n, "out_valid within 4096 cycles", 1, live_bit(out_valid));
      for a in 0 to 2 loop
        live_expect(AT, n, "rgb(" & integer'image(a) & ")", c5ref_sh_run(a), to_integer(unsigned(rgb(a))));
      end loop;
      live_expect(AT, n, "sat", c5ref_sh_run(3), to_integer(unsigned(sat)));
      edge(clk);
    end loop;
    live_pass(TB, SEED, integer'image(SAMPLES) & " samples");
  end process run;
end architecture sim;
