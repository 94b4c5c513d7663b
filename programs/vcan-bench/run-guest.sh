#!/usr/bin/env bash
# run-guest.sh --cache DIR --share DIR --timeout SECONDS
#
# Runs a payload on a virtual CAN bus. The build machines' kernels have no CAN at all, so this
# boots a throw-away qemu guest (software emulation: the machines' KVM cannot run a stock kernel)
# with Debian's amd64 kernel, which carries vcan, and a busybox initramfs with can-utils
# (candump, canplayer, cansend). The share directory is the guest's working directory, over 9p:
# the guest brings vcan0 up, runs `sh ./run.sh` there (busybox sh, not bash) with the share's bin/
# on PATH and lib/ on LD_LIBRARY_PATH (see copy-with-libs.sh) and powers off.
#
# Exit status: run.sh's; 124 if the guest ran out of time; 99 if it produced no result (did not
# boot, no vcan, crashed). The guest's console is kept as SHARE/console.log and printed on failure.
# The kernel is fetched once into the cache (Debian's linux-image package, ~80 MB, via apt; needs
# `scripts/setup.sh bench` and apt's package lists).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)

usage() { echo "usage: run-guest.sh --cache DIR --share DIR --timeout SECONDS" >&2; exit 2; }
die() { echo "run-guest: $*" >&2; exit 99; }
cache='' share='' timeout=''
while (($#)); do
  case $1 in
    --cache) cache=${2:-}; shift 2 || usage ;;
    --share) share=${2:-}; shift 2 || usage ;;
    --timeout) timeout=${2:-}; shift 2 || usage ;;
    *) usage ;;
  esac
done
[ -n "$cache" ] && [ -n "$share" ] && [[ $timeout =~ ^[0-9]+$ ]] || usage
[ -f "$share/run.sh" ] || { echo "run-guest: no run.sh in $share" >&2; exit 2; }
mkdir -p "$cache"
cache=$(realpath "$cache") share=$(realpath "$share")
work=$(mktemp -d "$cache/run.XXXXXX")
trap 'rm -rf "$work"' EXIT

# What the guest loads: CAN and vcan, and 9p over virtio-pci for the share (modprobe adds the
# dependencies; virtio-pci is the transport, not a dependency, so it is named).
MODULES="vcan can_raw virtio_pci 9pnet_virtio 9p"

# The kernel: the uncompressed vmlinux (qemu boots it through its PVH entry, twice as fast as a
# bzImage under emulation: no real-mode set-up, no decompression in the guest) and the modules
# above with their dependencies. Cached as linux-VERSION/, moved into place only when complete.
fetch_kernel() {
  local pkg kver dl out off m
  pkg=$(apt-cache depends linux-image-amd64 2>/dev/null | awk '/Depends: linux-image-[0-9]/ {print $2; exit}')
  [ -n "$pkg" ] || die "apt knows no linux-image-amd64 (run apt-get update)"
  kver=${pkg#linux-image-}
  echo "run-guest: fetching $pkg into $cache" >&2
  dl=$work/fetch
  mkdir -p "$dl"
  (cd "$dl" && apt-get download -qq "$pkg" >download.log 2>&1) || { cat "$dl/download.log" >&2; die "cannot download $pkg"; }
  dpkg-deb -x "$dl/$pkg"_*.deb "$dl/pkg"
  /sbin/depmod -b "$dl/pkg" "$kver"  # /sbin: not on a normal user's PATH
  out=$dl/linux-$kver
  mkdir -p "$out/lib/modules/$kver"
  # vmlinuz is a bzImage: set-up code, then the kernel as one xz stream.
  off=$(LC_ALL=C grep -obUaP '\xfd7zXZ\x00' "$dl/pkg/boot/vmlinuz-$kver" | awk -F: 'NR == 1 {print $1}')
  [ -n "$off" ] || die "no xz stream in vmlinuz-$kver"
  # (xz stops reading at the stream's end: in a pipe, tail would die of SIGPIPE.)
  xz -dc --single-stream <(tail -c +$((off + 1)) "$dl/pkg/boot/vmlinuz-$kver") >"$out/vmlinux"
  # modules.dep lists each module with its whole dependency closure. File names may spell a
  # module's _ as - (can-raw.ko): modprobe treats them alike.
  for m in $MODULES; do
    grep -E "(^|/)${m//[-_]/[-_]}\.ko:" "$dl/pkg/lib/modules/$kver/modules.dep" || die "$pkg has no module $m"
  done | sort -u >"$out/lib/modules/$kver/modules.dep"
  tr -d ':' <"$out/lib/modules/$kver/modules.dep" | tr ' ' '\n' | sort -u | while read -r m; do
    install -D -m644 "$dl/pkg/lib/modules/$kver/$m" "$out/lib/modules/$kver/$m"
  done
  # Another run may have finished first: then its copy stays.
  mv -T "$out" "$cache/linux-$kver" 2>/dev/null || true
  rm -rf "$dl"
}
kdir=$(find "$cache" -maxdepth 1 -name 'linux-*' -type d | sort -V | tail -1)
if [ -z "$kdir" ]; then
  fetch_kernel
  kdir=$(find "$cache" -maxdepth 1 -name 'linux-*' -type d | sort -V | tail -1)
fi

# The initramfs: busybox, the modules, can-utils and the guest's init. Rebuilt every run (under a
# second), so it always matches this script.
root=$work/root
mkdir -p "$root"/{bin,sbin,usr/bin,usr/sbin,dev,proc,sys,tmp,mnt}
cp -a "$kdir/lib" "$root/"
for b in /bin/busybox candump canplayer cansend; do "$here/copy-with-libs.sh" "$b" "$root"; done
cat >"$root/init" <<EOF
#!/bin/busybox sh
# PID 1 of the bench guest (programs/vcan-bench/run-guest.sh). Any failure before run.sh powers off
# without a result, which the host reports as 99.
/bin/busybox --install -s
mount -t devtmpfs dev /dev
exec </dev/console >/dev/console 2>&1
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t tmpfs tmp /tmp
fail() { echo "bench guest: \$*"; poweroff -f; }
for m in $MODULES; do modprobe \$m || fail "modprobe \$m failed"; done
ip link add dev vcan0 type vcan && ip link set up vcan0 || fail "cannot bring up vcan0"
mount -t 9p -o trans=virtio,version=9p2000.L,msize=262144 share /mnt || fail "cannot mount the share"
cd /mnt
PATH=/mnt/bin:\$PATH LD_LIBRARY_PATH=/mnt/lib sh ./run.sh
echo \$? >exit-status.tmp && mv exit-status.tmp exit-status
cd /
umount /mnt
poweroff -f
EOF
chmod 755 "$root/init"
(cd "$root" && find . | cpio -o -H newc -R 0:0 --quiet | gzip -1) >"$work/initrd.gz"

rm -f "$share/exit-status" "$share/console.log"
start=$SECONDS
qemu=0
timeout -k 5 "$timeout" qemu-system-x86_64 -accel tcg -m 512 -smp 1 -nodefaults -display none -no-reboot \
  -serial stdio -kernel "$kdir/vmlinux" -initrd "$work/initrd.gz" \
  -append "console=ttyS0 quiet loglevel=3 panic=-1" \
  -virtfs local,path="$share",mount_tag=share,security_model=none,id=share \
  </dev/null >"$share/console.log" 2>&1 || qemu=$?
if ((qemu == 124 || qemu == 137)); then
  status=124 why="timed out after $timeout s"
elif [ -s "$share/exit-status" ]; then
  status=$(cat "$share/exit-status") why="run.sh exited with $(cat "$share/exit-status")"
else
  status=99 why="the guest produced no result (qemu exit $qemu)"
fi
rm -f "$share/exit-status"
if ((status != 0)); then
  echo "---- guest console ($share/console.log) ----" >&2
  cat "$share/console.log" >&2
  echo "---- end of guest console ----" >&2
  echo "run-guest: $why" >&2
else
  echo "run-guest: run.sh passed in $((SECONDS - start)) s (boot included)"
fi
exit "$status"
