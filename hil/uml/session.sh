#!/bin/bash
# The inside of run-with-vcan.sh: creates the vcan interfaces, runs the command,
# leaves its exit code in "$MB2CO_VCAN_DIR/rc". Not meant to be called by hand.
#
# Environment (set by run-with-vcan.sh):
#   MB2CO_VCAN_DIR   host temp dir holding `request`, `env` (and for uml:
#                    `fstab`, `modroot/`, fifos `guest-stdout`/`guest-stderr`); receives
#                    `rc`, or `setup-error` (one line) when setup fails.
#   MB2CO_VCAN_MODE  uml:  this script is PID 1 of user-mode Linux (hostfs root,
#                          so the temp dir is the host's); it mounts, loads the
#                          CAN modules, relays output to consoles 1 and 2 and
#                          powers off at the end.
#                    host: this script runs in a fresh network namespace on the
#                          host; stdout/stderr are the caller's.
# Invariant: whatever the command leaves running (background jobs, daemons)
# dies when the command ends: it runs as the top of its own PID namespace.
# Cost: every exec takes ~50 ms inside user-mode Linux, so this script uses
# builtins where it can and one process per step (mount -a, modprobe -a, ip -batch).
set -u
export PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin
dir=${MB2CO_VCAN_DIR:?}
mode=${MB2CO_VCAN_MODE:?}
# shellcheck source=/dev/null
. "$dir/request" # MB2CO_ARGV MB2CO_CWD MB2CO_TIMEOUT_S MB2CO_IFACES [MB2CO_UML_MODROOT]

finish() {
  if [ "$mode" = uml ]; then
    sync # hostfs writes through, but mmap'ed files of the command may not have
    poweroff -f
  fi
  exit 0
}

setup_failed() {
  local msg=$*
  printf '%s\n' "${msg//$'\n'/ }" >"$dir/setup-error"
  finish
}

if [ "$mode" = uml ]; then
  out=$(mount -a -T "$dir/fstab" 2>&1) || setup_failed "mount: $out"
  out=$(modprobe -a -d "$MB2CO_UML_MODROOT" can-raw can-bcm vcan sch_plug 2>&1) || setup_failed "modprobe: $out"
fi
IFS=, read -r -a ifaces <<<"$MB2CO_IFACES"
batch="link set dev lo up"$'\n'
for i in "${ifaces[@]}"; do
  batch+="link add dev $i type vcan"$'\n'"link set dev $i up"$'\n'
done
out=$(ip -batch - 2>&1 <<<"$batch") || setup_failed "cannot create ${MB2CO_IFACES//,/ }: $out"

# The command gets the caller's environment and directory, no stdin (the
# terminal for --shell), a time limit (exit 124 and a line on stderr when it
# hits), and a PID namespace.
run_command() {
  local unshare timeout
  if ! unshare=$(type -P unshare) || ! timeout=$(type -P timeout); then
    echo "run-with-vcan: unshare or timeout missing" >&2
    return 125
  fi
  (
    set +u
    # shellcheck source=/dev/null
    . "$dir/env"
    cd -- "$MB2CO_CWD" 2>/dev/null ||
      { echo "run-with-vcan: working directory $MB2CO_CWD is not reachable" >&2; exit 125; }
    exec "$unshare" --pid --fork --kill-child --mount-proc -- \
      "$timeout" -v -k 5 "$MB2CO_TIMEOUT_S" "${MB2CO_ARGV[@]}"
  ) </dev/null
}

# --shell: inside UML the shell leads its own session with console 1 as its
# controlling tty (job control, Ctrl-C); on the host it stays in the caller's
# session and terminal. --foreground keeps `timeout` from moving it out of the
# terminal's foreground process group.
run_shell() {
  local lead=()
  [ "$mode" = host ] || lead=(setsid -w -c)
  (
    set +u
    # shellcheck source=/dev/null
    . "$dir/env"
    cd -- "$MB2CO_CWD" 2>/dev/null ||
      { echo "run-with-vcan: working directory $MB2CO_CWD is not reachable" >&2; exit 125; }
    exec unshare --pid --fork --kill-child --mount-proc -- \
      "${lead[@]}" timeout --foreground -k 5 "$MB2CO_TIMEOUT_S" "${MB2CO_ARGV[@]}"
  )
}

if [ -n "${MB2CO_SHELL:-}" ]; then
  if [ "$mode" = uml ]; then
    read -r rows cols <<<"${MB2CO_TTY_SIZE:-24 80}"
    stty -F /dev/tty1 sane rows "$rows" cols "$cols"
    run_shell </dev/tty1 >/dev/tty1 2>&1
  else
    run_shell
  fi
  rc=$?
elif [ "$mode" = uml ]; then
  # The command writes into pipes (as it would on the host); relays copy them
  # to consoles 1 and 2, which the host wired to its stdout and stderr. The
  # fifos live on hostfs but behave as guest-local pipes.
  stty -F /dev/tty1 raw -echo
  stty -F /dev/tty2 raw -echo
  cat "$dir/guest-stdout" >/dev/tty1 &
  relay_out=$!
  cat "$dir/guest-stderr" >/dev/tty2 &
  relay_err=$!
  run_command >"$dir/guest-stdout" 2>"$dir/guest-stderr"
  rc=$?
  # All writers are gone with the PID namespace; a relay's last close of its
  # console waits until the host has taken every byte.
  wait "$relay_out" "$relay_err"
else
  run_command
  rc=$?
fi
echo "$rc" >"$dir/rc"
finish
