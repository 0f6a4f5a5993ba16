# rtaccel on the ZC706: package the IP from build/verilog, build a block design
# (PS7, the PL DDR3 through a MIG, the IP, its interrupt) and a bitstream.
#
# NOT RUN: no Vivado here. Written from Xilinx's documented Tcl commands
# (UG835 Tcl Command Reference; UG1118 Creating and Packaging Custom IP;
# UG994 Designing IP Subsystems Using IP Integrator) and never tried on a
# board. Expect to adjust it on the first real run.
#
# Usage (Vivado 2019.1 or later, ZC706 board files installed with Vivado):
#   make verilog                     # SystemVerilog of the top into build/verilog/
#   vivado -mode batch -source fpga/zc706/build.tcl -tclargs [verilog_dir] [out_dir] [top] [accel_mhz]
# Defaults: build/verilog build/zc706 rtaccel_system 200.

set verilog   [expr {[llength $argv] > 0 ? [lindex $argv 0] : "build/verilog"}]
set out       [expr {[llength $argv] > 1 ? [lindex $argv 1] : "build/zc706"}]
set top       [expr {[llength $argv] > 2 ? [lindex $argv 2] : "rtaccel_system"}]
# Accelerator clock (PS FCLK_CLK0). docs/fmax.md has the estimate it should be checked against.
set accel_mhz [expr {[llength $argv] > 3 ? [lindex $argv 3] : 200}]
set part  xc7z045ffg900-2
set board xilinx.com:zc706:part0

# ---- 1. Package the IP (UG1118): the ports are named m_axi_*, s_axi_*,
# aclk, aresetn and interrupt, so the packager infers the AXI4 master, the
# AXI4-Lite slave, the clock, the reset and the interrupt from the names.
create_project -force ${top}_ip $out/ip_project -part $part
add_files [glob $verilog/*.sv]
set_property top $top [current_fileset]
update_compile_order -fileset sources_1
ipx::package_project -root_dir $out/ip -vendor rtaccel -library user -taxonomy /UserIP -import_files -set_current true
ipx::associate_bus_interfaces -busif m_axi -clock aclk [ipx::current_core]
ipx::associate_bus_interfaces -busif s_axi -clock aclk [ipx::current_core]
set_property core_revision 1 [ipx::current_core]
ipx::create_xgui_files [ipx::current_core]
ipx::update_checksums [ipx::current_core]
ipx::save_core [ipx::current_core]
close_project

# ---- 2. The ZC706 project and block design (UG994).
create_project -force rtaccel_zc706 $out/project -part $part
set_property board_part $board [current_project]
set_property ip_repo_paths [file normalize $out/ip] [current_project]
update_ip_catalog
create_bd_design system

# PS7 with the board preset (PS DDR, MIO, clocks), GP0 master, fabric interrupts, FCLK_CLK0 for the accelerator.
set ps [create_bd_cell -type ip -vlnv xilinx.com:ip:processing_system7 ps7]
apply_bd_automation -rule xilinx.com:bd_rule:processing_system7 \
  -config {make_external "FIXED_IO, DDR" apply_board_preset "1" Master "Disable" Slave "Disable"} $ps
set_property -dict [list CONFIG.PCW_USE_M_AXI_GP0 {1} CONFIG.PCW_USE_FABRIC_INTERRUPT {1} \
  CONFIG.PCW_IRQ_F2P_INTR {1} CONFIG.PCW_FPGA0_PERIPHERAL_FREQMHZ $accel_mhz] $ps

# The PL DDR3 SODIMM through a MIG 7-series, configured from the board file
# (DDR3-1600, 64-bit, 4:1: ui_clk 200 MHz, a 512-bit AXI4 slave: the width
# rtaccel_system's m_axi has). Its system clock is the board's 200 MHz
# differential clock; its reset comes from the PS (active low).
set mig [create_bd_cell -type ip -vlnv xilinx.com:ip:mig_7series mig]
apply_bd_automation -rule xilinx.com:bd_rule:mig_7series -config {Board_Interface "ddr3_sdram"} $mig
if {[llength [get_bd_nets -quiet -of_objects [get_bd_pins mig/sys_rst]]] == 0} {
  connect_bd_net [get_bd_pins ps7/FCLK_RESET0_N] [get_bd_pins mig/sys_rst]
}

# The accelerator on FCLK_CLK0.
set acc [create_bd_cell -type ip -vlnv rtaccel:user:$top:1.0 accel]

# PS GP0 -> accelerator registers (an AXI interconnect with its reset block is
# inserted); accelerator m_axi -> MIG (a SmartConnect, which also crosses from
# FCLK_CLK0 to the MIG's ui_clk).
apply_bd_automation -rule xilinx.com:bd_rule:axi4 -config [list Clk_master {/ps7/FCLK_CLK0} \
  Clk_slave {/ps7/FCLK_CLK0} Clk_xbar {/ps7/FCLK_CLK0} Master {/ps7/M_AXI_GP0} Slave {/accel/s_axi} \
  intc_ip {New AXI Interconnect} master_apm {0}] [get_bd_intf_pins accel/s_axi]
apply_bd_automation -rule xilinx.com:bd_rule:axi4 -config [list Clk_master {/ps7/FCLK_CLK0} \
  Clk_slave {/mig/ui_clk} Clk_xbar {/mig/ui_clk} Master {/accel/m_axi} Slave {/mig/S_AXI} \
  intc_ip {New AXI SmartConnect} master_apm {0}] [get_bd_intf_pins mig/S_AXI]
connect_bd_net [get_bd_pins accel/interrupt] [get_bd_pins ps7/IRQ_F2P]

# Addresses: the registers in the GP0 window (4 KB), the whole SODIMM in the accelerator's space.
assign_bd_address
validate_bd_design
save_bd_design

# ---- 3. Wrapper, synthesis, implementation, bitstream.
set bd [get_files system.bd]
generate_target all $bd
set wrapper [make_wrapper -files $bd -top]
# Older releases keep the wrapper under .srcs, newer under .gen.
if {$wrapper eq ""} { set wrapper [lindex [glob -nocomplain $out/project/*/sources_1/bd/system/hdl/system_wrapper.v] 0] }
add_files -norecurse $wrapper
set_property top system_wrapper [current_fileset]
update_compile_order -fileset sources_1
launch_runs impl_1 -to_step write_bitstream -jobs 4
wait_on_run impl_1
open_run impl_1
report_timing_summary -file $out/timing_summary.rpt
report_utilization -hierarchical -file $out/utilization.rpt
puts "rtaccel: bitstream in [get_property DIRECTORY [get_runs impl_1]]; timing in $out/timing_summary.rpt"
