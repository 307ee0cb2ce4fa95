#!/usr/bin/env bash
# Replaces the README's field tables (between <!-- fields:NAME --> markers) with the ones the
# kind declarations make (core/include/tessera/scene/schema/kinds.hpp). Run after changing a
# declaration; the unit test SchemaDocs.ReadmeTablesAreTheDeclarations fails until you do.
#   scripts/update-readme-tables.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
cmake --build "$build" --target tessera-schema-docs >/dev/null
"$build/bench/scene/tessera-schema-docs" > "$build/readme-tables.md"
/usr/bin/python3 - "$build/readme-tables.md" <<'PY'
import re, sys
blocks = open(sys.argv[1]).read()
readme = open("README.md").read()
for m in re.finditer(r"<!-- fields:(\w+) -->\n.*?<!-- /fields:\1 -->", blocks, re.S):
    name = m.group(1)
    pattern = re.compile(r"<!-- fields:%s -->\n.*?<!-- /fields:%s -->" % (name, name), re.S)
    if not pattern.search(readme):
        sys.exit("README.md has no <!-- fields:%s --> block" % name)
    readme = pattern.sub(lambda _: m.group(0), readme)
open("README.md", "w").write(readme)
PY
echo "README.md tables updated"
