#!/usr/bin/env bash
# check-m7-image.sh ELF — prints the Cortex-M7 image's .text/.data/.bss and fails if it contains a
# heap (malloc and friends, operator new/delete, _sbrk) or C++ exception machinery: the firmware
# core must never allocate after start-up and never throw (docs/onboard.md, "No heap after start-up"), and on the MCU the linker
# only pulls these in if something calls them.
set -euo pipefail
elf=${1:?usage: check-m7-image.sh ELF}
[ -f "$elf" ] || { echo "check-m7-image: no such file: $elf" >&2; exit 2; }

# Berkeley format: text (code, constants, vectors), data (initialised RAM, also held in flash), bss.
arm-none-eabi-size -B "$elf"

# nm -C prints "[address] type name"; the demangled name may contain spaces, so strip the first
# two fields rather than splitting.
symbols=$(arm-none-eabi-nm -C "$elf" | sed -E 's/^[0-9a-f]* *[A-Za-z] //')
forbidden=$(grep -E '^(_?(malloc|free|calloc|realloc)(_r)?|_sbrk(_r)?|__cxa_throw|__cxa_allocate_exception|__gxx_personality_v0)$|^operator (new|delete)' \
  <<<"$symbols" | sort -u | paste -sd, -) || true
if [ -n "$forbidden" ]; then
  echo "check-m7-image: $elf uses the heap or exceptions: $forbidden" >&2
  exit 1
fi
echo "check-m7-image: $elf: no heap, no exceptions"
