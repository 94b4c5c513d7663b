#!/usr/bin/env bash
# copy-with-libs.sh BIN DESTROOT — copies a program and the shared libraries it loads into a tree
# that the bench guest (busybox, no libraries of its own) can run it from:
#   DESTROOT/bin/NAME, DESTROOT/lib/<each library ldd lists>, the ELF interpreter at its own path.
# For the initramfs DESTROOT is the guest's /, whose loader searches /lib. For a payload it is the
# share: the guest puts the share's bin/ on PATH and lib/ on LD_LIBRARY_PATH, so run.sh calls NAME.
# BIN may be a path or a command on PATH.
set -euo pipefail
bin=$(command -v "${1:?usage: copy-with-libs.sh BIN DESTROOT}") || { echo "copy-with-libs: no program $1" >&2; exit 2; }
root=${2:?usage: copy-with-libs.sh BIN DESTROOT}

install -D -m755 "$bin" "$root/bin/$(basename "$bin")"
# ldd refuses a static program ("not a dynamic executable"): nothing more to copy then.
deps=$(ldd "$bin" 2>/dev/null) || exit 0
while read -r name arrow path _; do
  if [ "$arrow" = "=>" ]; then
    [ "$path" != "not" ] || { echo "copy-with-libs: $bin: $name not found" >&2; exit 1; }
    install -D -m644 "$(realpath "$path")" "$root/lib/$name"
  elif [[ $name == /* ]]; then  # the interpreter, which the program names by absolute path
    install -D -m755 "$(realpath "$name")" "$root$name"
  fi                            # else linux-vdso.so.1, which the kernel provides
done <<<"$deps"
