#!/usr/bin/env bash
# Regenerates the parameter tables in docs/levels.md from the code (`proxygrasp params --markdown`).
#   bash scripts/update-docs.sh [path/to/proxygrasp]
set -euo pipefail
cd "$(dirname "$0")/.."
exe="${1:-build/release/proxygrasp}"
tables=$(mktemp)
trap 'rm -f "$tables"' EXIT
"$exe" params --markdown > "$tables"
python3 - "$tables" <<'PY'
import sys
path = "docs/levels.md"
text = open(path).read()
generated = open(sys.argv[1]).read()
begin, end = "<!-- params:begin -->\n", "<!-- params:end -->"
b, e = text.index(begin), text.index(end)
open(path, "w").write(text[: b + len(begin)] + generated + text[e:])
PY
echo "update-docs: docs/levels.md parameter tables regenerated"
