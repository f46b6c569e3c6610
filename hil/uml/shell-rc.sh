# The startup file of run-with-vcan.sh --shell's bash (not ~/.bashrc: it
# could reset PATH, which holds the build's programs first).
# shellcheck shell=bash
PS1='(vcan) \w\$ '
echo "run-with-vcan: a shell with $(ip -br link show type vcan | awk '{ printf "%s%s", sep, $1; sep = ", " }') up; 'exit' ends it"
