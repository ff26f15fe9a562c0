#!/usr/bin/env bash
# Cargo runner for thumbv7em-none-eabihf (see .cargo/config.toml): runs a test ELF on an
# emulated Cortex-M4F (QEMU mps2-an386) and decodes its defmt log with defmt-print.
# The program's semihosting exit status becomes this script's status (pipefail), so a failing
# on-target test fails `cargo test`. QEMU's semihosting output is on stdout; stderr stays apart.
set -euo pipefail
elf="$1"
timeout "${DEFORM_QEMU_TIMEOUT:-300}" qemu-system-arm \
    -machine mps2-an386 -cpu cortex-m4 \
    -display none -monitor none -serial none \
    -semihosting-config enable=on,target=native \
    -kernel "$elf" | defmt-print -e "$elf"
