#!/usr/bin/env bash
# Installs the Debian/Ubuntu packages cube5 needs, only those missing. Called by the
# Makefile before the first build; safe to run again. Uses sudo when not root.
# With arguments, installs those packages instead (e.g. python3-vtk9 for `make bench-peer`).
set -euo pipefail
pkgs=(build-essential g++ pkg-config zlib1g-dev
      python3               # test and bench scripts read JSON with it
      libjansson-dev        # scene files (JSON)
      libteem-dev           # NRRD volumes (Teem's nrrd)
      libopenimageio-dev    # PNG / EXR output (OpenImageIO)
      libusb-1.0-0-dev      # the host driver's USB transport (host_driver/)
      umockdev libumockdev-dev # the emulated board as a USB device (board_emu/, tests/link_test.sh)
      groff-base            # tests/man_test.sh renders man/*.1 with groff
      gnuplot-nox           # cube5 sweep draws sweep.png with it (pngcairo; tests/cli_test.sh), make results
      ghdl ghdl-mcode       # VHDL-2008 simulation and --synth of fpga/ (mcode: the backend
                            # that runs in place, no compiler needed; tests/fpga_test.sh)
      yosys                 # synthesis for iCE40 (make fpga-report)
      nextpnr-ice40         # place and route, Fmax (make fpga-report)
      fpga-icestorm)        # iCE40 tools (icepack, icetime) beside nextpnr (make fpga-report)
[ $# -eq 0 ] || pkgs=("$@")
missing=()
for p in "${pkgs[@]}"; do
  [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null)" = "install ok installed" ] || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "setup: installing ${missing[*]}" >&2
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
