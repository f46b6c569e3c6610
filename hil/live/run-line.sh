#!/bin/sh
# The line, live: N stations (mb2co-node + mb2co-plant, or real gateways with
# --serial), the stop2 scenario, checked. Options: run_line.py, docs/mini-project.md.
# /usr/bin/python3 (the system's, standard library only) whatever PATH says.
exec /usr/bin/python3 "$(dirname "$0")/run_line.py" "$@"
