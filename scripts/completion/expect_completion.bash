# The completion tests' one check (tests/cli/completion_test.sh,
# tests/master/completion_test.sh): source after mb2co.bash, call
#   expect "WORD..." PROGRAM WORD... ""
# to ask _mb2co_complete what bash would offer at a TAB after the words (the
# last one is under the cursor); a difference is printed and sets failed=1.
# Not installed: only mb2co.bash is (CMakeLists.txt).
# shellcheck shell=bash disable=SC2034  # failed is the sourcing test's exit status
failed=0
expect() {
  local want=$1
  shift
  COMP_WORDS=("$@")
  COMP_CWORD=$(($# - 1))
  _mb2co_complete
  if [[ "${COMPREPLY[*]}" != "$want" ]]; then
    echo "completion of '$*': got '${COMPREPLY[*]}', want '$want'" >&2
    failed=1
  fi
}
