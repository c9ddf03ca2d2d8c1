#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Puts "SPDX-License-Identifier: Apache-2.0" at the top of MorphMill's own source files that lack
# one (after a #! line), in the file's comment style. Idempotent. `--check` only lists the files
# that lack it and exits 1 if there are any. Third-party files (data/, LICENSES/) are left alone:
# their licences are listed in data/README.md.
set -euo pipefail
cd "$(dirname "$0")/.."
check=0
[[ "${1:-}" == "--check" ]] && check=1

missing=0
while IFS= read -r file; do
  [[ -f "$file" ]] || continue
  if head -n 5 "$file" | grep -q "SPDX-License-Identifier"; then continue; fi
  missing=$((missing + 1))
  if ((check)); then echo "no SPDX line: $file"; continue; fi
  case "$file" in
    *.h | *.cpp) line="// SPDX-License-Identifier: Apache-2.0" ;;
    *) line="# SPDX-License-Identifier: Apache-2.0" ;;
  esac
  if head -n 1 "$file" | grep -q '^#!'; then
    sed -i "1a $line" "$file"
  else
    sed -i "1i $line" "$file"
  fi
done < <(git ls-files -- '*.h' '*.cpp' '*.py' '*.sh' '*.cmake' '*.in' '*CMakeLists.txt' 'Makefile' '.ci/run' |
         grep -v -E '^(data|LICENSES)/')

if ((check)); then
  ((missing == 0)) && echo "spdx: every source file has its SPDX line"
  ((missing == 0))
else
  echo "spdx: added the SPDX line to $missing file(s)"
fi
