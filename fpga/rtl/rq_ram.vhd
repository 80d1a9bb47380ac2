-- A simple dual-port RAM: one synchronous write port, one synchronous (registered) read
-- port, no reset. The shape every FPGA block RAM and an eDRAM macro share, so synthesis
-- maps it to block RAM (SB_RAM40_4K on iCE40) rather than flip-flops. A read of the
-- address written at the same edge returns the old data; callers never rely on it
-- (ray_queue.vhd bypasses that case, rq_addr_alloc.vhd never reads what it writes).
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

entity rq_ram is
  generic (
    DEPTH     : positive;
    ADDR_BITS : positive;
    DATA_BITS : positive);
  port (
    clk   : in  std_logic;
    we    : in  std_logic;
    waddr : in  std_logic_vector(ADDR_BITS - 1 downto 0);
    wdata : in  std_logic_vector(DATA_BITS - 1 downto 0);
    re    : in  std_logic;
    raddr : in  std_logic_vector(ADDR_BITS - 1 downto 0);
    rdata : out std_logic_vector(DATA_BITS - 1 downto 0));  -- mem(raddr) of the last edge with re
end entity rq_ram;

architecture rtl of rq_ram is
  type mem_t is array (0 to DEPTH - 1) of std_logic_vector(DATA_BITS - 1 downto 0);
  signal mem : mem_t;
begin
  process (clk)
  begin
    if rising_edge(clk) then
      if we = '1' then
        mem(to_integer(unsigned(waddr))) <= wdata;
      end if;
      if re = '1' then
        rdata <= mem(to_integer(unsigned(raddr)));
      end if;
    end if;
  end process;
end architecture rtl;
