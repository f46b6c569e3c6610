#!/bin/bash
# Runs a command with virtual CAN interfaces up, also on kernels without AF_CAN.
#
# Usage: hil/uml/run-with-vcan.sh [--ifaces vcan0,vcan1] [--timeout SEC]
#                                 [--mode auto|host|uml] -- COMMAND [ARGS...]
#        hil/uml/run-with-vcan.sh [--ifaces ...] [--mode ...] [--build DIR] --shell
#
# auto (default): as root, try the host kernel first (fresh network namespace,
# `ip link add type vcan`); otherwise, or when that fails, boot user-mode Linux
# (Debian user-mode-linux, hostfs root = the host's /, CAN modules by modprobe).
# Either way the command sees its own private vcan interfaces (parallel runs do
# not share a bus), the caller's working directory and environment, stdin
# /dev/null, and runs in its own PID namespace: background processes it leaves
# die when it ends. Its stdout/stderr reach ours.
#
# --shell (also the default when no command is given and stdin is a terminal):
# an interactive bash on this terminal instead of a command, for typing the
# labs (docs/labs.md): the vcan interfaces up, the directories of the build's
# programs (mb2co-*, found under --build DIR, default build/ of this checkout)
# first on PATH, no time limit unless --timeout; `exit` ends it. The terminal
# is in raw mode meanwhile (Ctrl-C reaches the guest's shell) and restored.
#
# Exit status: the command's (124 when --timeout hit it, 128+N for signal N);
# 125 with one line on stderr when the sandbox could not be set up or an option
# is bad (not 2: that may be the command's own); --help: this text, exit 0;
# --version: the project's version (CMakeLists.txt), exit 0.
# Environment: MB2CO_VCAN_MODE (same as --mode), MB2CO_UML_MEM (default 512M),
# MB2CO_VCAN_KEEP=1 keeps the run's temp dir (request, console.log) for a look.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
session=$here/session.sh
ifaces=vcan0
timeout_s=600
timeout_given=""
shell=""
build=$here/../../build
mode=${MB2CO_VCAN_MODE:-auto}

die() {
  echo "run-with-vcan: $*" >&2
  exit 125
}
usage_line="usage: run-with-vcan.sh [--ifaces vcan0,vcan1] [--timeout SEC] [--mode auto|host|uml] -- COMMAND [ARGS...] | --shell"
# --help is an answer, not an error (docs/cli.md): the usage on stdout, exit 0.
help() {
  echo "$usage_line"
  sed -n '2,/^set -euo/{/^set -euo/d;s/^# \{0,1\}//;p}' "${BASH_SOURCE[0]}" | sed '1,/^Usage/{/^Usage/d;d}' | sed '1,/^$/d'
  exit 0
}

while (($#)); do
  case $1 in
    --ifaces | --timeout | --mode | --build) (($# >= 2)) || die "$1 needs a value" ;;&
    --ifaces) ifaces=$2; shift 2 ;;
    --timeout) timeout_s=$2; timeout_given=1; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --shell) shell=1; shift ;;
    --mode) mode=$2; shift 2 ;;
    --) shift; break ;;
    -h | --help) help ;;
    --version) echo "run-with-vcan.sh $(sed -n 's/^project(mb2co VERSION \([0-9.]*\).*/\1/p' "$here/../../CMakeLists.txt")"; exit 0 ;;
    *) die "unknown option $1, the command goes after -- (try run-with-vcan.sh --help)" ;;
  esac
done
if [ -n "$shell" ]; then
  (($# == 0)) || die "--shell takes no command"
elif (($# == 0)); then
  { [ -t 0 ] && [ -t 1 ]; } || die "missing operand: -- COMMAND [ARGS...], or a terminal for the shell (try run-with-vcan.sh --help)"
  shell=1
fi
if [ -n "$shell" ]; then
  { [ -t 0 ] && [ -t 1 ]; } || die "--shell needs a terminal on stdin and stdout"
  [ -n "$timeout_given" ] || timeout_s=999999
  set -- bash --rcfile "$here/shell-rc.sh" -i
fi
[[ $ifaces =~ ^[A-Za-z0-9_]{1,15}(,[A-Za-z0-9_]{1,15})*$ ]] ||
  die "--ifaces must be comma-separated names of at most 15 characters [A-Za-z0-9_], got \"$ifaces\""
[[ $timeout_s =~ ^[1-9][0-9]{0,5}$ ]] || die "--timeout must be whole seconds 1..999999, got \"$timeout_s\""
case $mode in auto | host | uml) ;; *) die "--mode must be auto, host or uml, got \"$mode\"" ;; esac
[[ $session != *[[:space:]]* ]] || die "the checkout path must not contain blanks: $here"

base=${TMPDIR:-/tmp}
case $base in /dev/* | /proc/* | /sys/* | *[[:space:]]*) base=/tmp ;; esac
dir=$(mktemp -d "$base/mb2co-vcan.XXXXXX") || die "cannot create a temp dir in $base"

uml_pid=""
relays=()
input_relay=""
saved_tty=""
# shellcheck disable=SC2317  # called from the EXIT trap
cleanup() {
  # The UML `timeout` leads a process group; a ptrace-stopped UML helper can
  # outlive the kernel, so the whole group goes.
  if [ -n "$uml_pid" ]; then
    kill -KILL -- "-$uml_pid" 2>/dev/null || true
    { wait "$uml_pid"; } 2>/dev/null || true # reaped quietly (no "Killed" line)
  fi
  [ -z "$input_relay" ] || kill "$input_relay" 2>/dev/null || true
  [ -z "$saved_tty" ] || stty "$saved_tty" 2>/dev/null || true
  ((${#relays[@]} == 0)) || kill "${relays[@]}" 2>/dev/null || true
  if [ -n "${MB2CO_VCAN_KEEP:-}" ]; then
    echo "run-with-vcan: kept $dir" >&2
  else
    rm -rf -- "$dir"
  fi
}
trap cleanup EXIT
trap 'exit 143' TERM
trap 'exit 130' INT
trap 'exit 129' HUP

# The request the session reads; the environment as exports (no shell state).
MB2CO_ARGV=("$@")
{
  declare -p MB2CO_ARGV
  printf 'MB2CO_CWD=%q\nMB2CO_TIMEOUT_S=%q\nMB2CO_IFACES=%q\nMB2CO_SHELL=%q\n' "$PWD" "$timeout_s" "$ifaces" "$shell"
  # The guest's terminal gets the size of ours (a tty of UML starts at 0x0).
  [ -z "$shell" ] || printf 'MB2CO_TTY_SIZE=%q\n' "$(stty size 2>/dev/null || echo '24 80')"
} >"$dir/request"
while IFS= read -r name; do
  case $name in PWD | OLDPWD | SHLVL | _ | SHELLOPTS | BASHOPTS | MB2CO_VCAN_*) continue ;; esac
  printf 'export %s=%q\n' "$name" "${!name}"
done < <(compgen -e) >"$dir/env"
if [ -n "$shell" ]; then
  # The folders holding the build's programs, first on the shell's PATH.
  tools=""
  if [ -d "$build" ]; then
    tools=$(find "$build" -path '*/CMakeFiles' -prune -o -type f -perm -u+x -name 'mb2co-*' -printf '%h\n' |
      sort -u | paste -sd:)
  fi
  [ -n "$tools" ] || echo "run-with-vcan: no mb2co-* programs under $build (build them, or give --build DIR)" >&2
  printf 'export PATH=%q\n' "${tools:+$tools:}$PATH" >>"$dir/env"
fi

# Exit with the command's code if the session ran it; return if it did not.
exit_with_session_rc() {
  local rc
  rc=$(cat "$dir/rc" 2>/dev/null) || return 0
  [[ $rc =~ ^[0-9]{1,3}$ ]] && exit "$rc"
}

# --- host kernel: a throw-away probe keeps a failing attempt silent ----------
host_can_vcan() {
  [ "$(id -u)" = 0 ] && command -v unshare >/dev/null &&
    unshare --net -- ip link add dev vcan0 type vcan >/dev/null 2>&1
}
if [ "$mode" != uml ] && host_can_vcan; then
  # In the foreground, so that the command keeps default SIGINT handling
  # (background jobs of a script start with SIGINT ignored).
  set +e
  MB2CO_VCAN_DIR=$dir MB2CO_VCAN_MODE=host unshare --net --kill-child -- "$session"
  host_rc=$?
  set -e
  exit_with_session_rc
  die "host kernel setup failed: $(cat "$dir/setup-error" 2>/dev/null || echo "unshare exit $host_rc")"
elif [ "$mode" = host ]; then
  die "the host kernel cannot create vcan interfaces here (needs root, unshare and the vcan module)"
fi

# --- user-mode Linux -----------------------------------------------------------
command -v linux.uml >/dev/null || die "linux.uml not found (apt-get install user-mode-linux)"
command -v modprobe >/dev/null || die "modprobe not found (apt-get install kmod)"
command -v ip >/dev/null || die "ip not found (apt-get install iproute2)"
uml_version=$(linux.uml --version 2>/dev/null) || die "linux.uml --version failed"
modules=/usr/lib/uml/modules/$uml_version/kernel
[ -f "$modules/drivers/net/can/vcan.ko" ] || die "no vcan module for UML $uml_version in $modules"
[[ $dir != *[[:space:]]* ]] || die "temp dir path must not contain blanks: $dir"
uml_mem=${MB2CO_UML_MEM:-512M}
[[ $uml_mem =~ ^([1-9][0-9]{0,5})([KMG])$ ]] || die "bad MB2CO_UML_MEM '$uml_mem' (like 512M)"
mem_kib=${BASH_REMATCH[1]}
case ${BASH_REMATCH[2]} in M) mem_kib=$((mem_kib * 1024)) ;; G) mem_kib=$((mem_kib * 1048576)) ;; esac
# The guest's RAM is a sparse file, on /dev/shm by default: a small /dev/shm
# (64 MiB in a default container) would kill the guest with SIGBUS mid-run.
mem_dir=/dev/shm
shm_kib=$(df -Pk /dev/shm 2>/dev/null | awk 'NR == 2 { print $4 }') || shm_kib=0
((${shm_kib:-0} >= mem_kib)) || mem_dir=$base
mkdir -p "$dir/modroot/lib"
ln -s /usr/lib/uml/modules "$dir/modroot/lib/modules"
printf 'MB2CO_UML_MODROOT=%q\n' "$dir/modroot" >>"$dir/request"
cat >"$dir/fstab" <<'EOF'
proc    /proc    proc   defaults 0 0
sysfs   /sys     sysfs  defaults 0 0
devpts  /dev/pts devpts newinstance,ptmxmode=0666,mode=0620,X-mount.mkdir 0 0
tmpfs   /dev/shm tmpfs  mode=1777,X-mount.mkdir 0 0
EOF

# Relays: UML puts its console fds in O_NONBLOCK mode, which must not leak into
# the caller's stdout/stderr (a shared pipe or terminal); fifos isolate them.
# The guest's fifos (guest-*) are created here too: on hostfs they act as
# pipes local to the guest kernel, unrelated to the host's.
mkfifo "$dir/host-stdout" "$dir/host-stderr" "$dir/guest-stdout" "$dir/guest-stderr"
cat "$dir/host-stdout" &
relays+=($!)
cat "$dir/host-stderr" >&2 &
relays+=($!)
# --shell: console 1 reads our terminal too, through a fifo for the same
# reason. Ours goes raw: the guest's tty does the line editing, echo and
# Ctrl-C; a second echo or a SIGINT here would be wrong.
console1=null,fd:3
if [ -n "$shell" ]; then
  mkfifo "$dir/host-stdin"
  exec 6<>"$dir/host-stdin" 7<&0
  saved_tty=$(stty -g)
  stty raw -echo
  cat <&7 >"$dir/host-stdin" &
  input_relay=$!
  console1=fd:6,fd:3
fi

# Boot parameters from DESIGN.md §10 (quick boot) plus skipping the raid6
# benchmark (0.85 s; nothing here uses md-raid or btrfs); con0 is the kernel
# console (log file), con1/con2 carry the command's stdout/stderr.
set +e
TMPDIR=$mem_dir timeout -k 5 $((timeout_s + 120)) linux.uml \
  mem="$uml_mem" root=/dev/root rootfstype=hostfs rootflags=/ rw \
  init="$session" con=null ssl=null con0=null,fd:5 con1=$console1 con2=null,fd:4 \
  pty.legacy_count=0 cryptomgr.notests zswap.enabled=0 initcall_blacklist=raid6_select_algo quiet \
  MB2CO_VCAN_DIR="$dir" MB2CO_VCAN_MODE=uml \
  </dev/null 3>"$dir/host-stdout" 4>"$dir/host-stderr" 5>"$dir/console.log" >>"$dir/console.log" 2>&1 &
uml_pid=$!
# Quietly: bash would print a job line when UML dies by a signal (see below).
{ wait "$uml_pid"; } 2>/dev/null
uml_rc=$?
set -e
kill -KILL -- "-$uml_pid" 2>/dev/null || true
uml_pid=""
if [ -n "$input_relay" ]; then
  kill "$input_relay" 2>/dev/null || true
  input_relay=""
fi
wait "${relays[@]}" 2>/dev/null || true
relays=()

# The exit code comes from the file: ~1 boot in 40 aborts (SIGABRT) at poweroff
# after the command has finished.
exit_with_session_rc
if [ -f "$dir/setup-error" ]; then
  die "user-mode Linux setup failed: $(cat "$dir/setup-error")"
fi
last=$(grep -v '^[[:space:]]*$' "$dir/console.log" 2>/dev/null | tail -n 1 | tr -d '\r')
die "user-mode Linux did not run the command (linux.uml exit $uml_rc${last:+; last console line: $last})"
