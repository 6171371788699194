#!/usr/bin/env bash
# Regenerates the parameter tables in docs/levels.md (`proxygrasp params --markdown`) and the table of
# live and restart parameters in docs/app.md (`proxygrasp params --liveness`) from the code.
#   bash scripts/update-docs.sh [path/to/proxygrasp]
set -euo pipefail
cd "$(dirname "$0")/.."
exe="${1:-build/release/proxygrasp}"
generated=$(mktemp)
trap 'rm -f "$generated"' EXIT
# replace(doc, marker, command...): the text between <!-- marker:begin --> and <!-- marker:end -->
replace() {
  local doc="$1" marker="$2"
  shift 2
  "$@" > "$generated"
  python3 - "$doc" "$marker" "$generated" <<'PY'
import sys
path, marker, generated = sys.argv[1], sys.argv[2], open(sys.argv[3]).read()
text = open(path).read()
begin, end = "<!-- %s:begin -->\n" % marker, "<!-- %s:end -->" % marker
b, e = text.index(begin), text.index(end)
open(path, "w").write(text[: b + len(begin)] + generated + text[e:])
PY
}
replace docs/levels.md params "$exe" params --markdown
replace docs/app.md liveness "$exe" params --liveness
echo "update-docs: docs/levels.md parameter tables and docs/app.md liveness table regenerated"
