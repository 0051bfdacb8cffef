#!/usr/bin/env bash
# The layout gates (issue 47): every C++ file as .clang-format lays it out (120 columns), the function-length
# ratchet (proptests/style/long_functions.txt only shrinks) and the copied-code ratchet (proptests/style/copies.txt
# only shrinks: a new run of 6 lines standing twice in the library fails).  Exit non-zero on a finding.
# Usage: bash proptests/gates.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/setup --gates
status=0
mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h' 2>/dev/null || find reference fast cli proptests bench -name '*.[ch]pp')
if ! clang-format --style=file --dry-run -Werror "${files[@]}" > build-format.log 2>&1; then
  status=1
  head -60 build-format.log
  echo "gates: $(grep -cE '(warning|error): code should be clang-formatted' build-format.log) lines not as .clang-format lays them out: run clang-format -i on the files named"
fi
rm -f build-format.log
python3 proptests/style/function_lengths.py . || status=1
python3 proptests/style/copies.py . || status=1
[ $status -eq 0 ] && echo "gates: layout, function lengths and copies clean ($(echo "${#files[@]}") files)"
exit $status
