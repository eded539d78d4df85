# Sourced by the report scripts. replace_doc_section DOC NAME SECTION_FILE: the lines of DOC from
# `<!-- NAME:begin -->` to `<!-- NAME:end -->` become SECTION_FILE's lines (which carry the two
# markers themselves); the rest of DOC is kept as it was.
replace_doc_section() {
  local doc=$1 name=$2 section=$3 rewritten
  rewritten=$(mktemp "${TMPDIR:-/tmp}/doc-section.XXXXXX")
  awk -v section="$section" -v begin="<!-- $name:begin -->" -v end="<!-- $name:end -->" '
    $0 == begin { while ((getline line < section) > 0) print line; skipping = 1; next }
    $0 == end { skipping = 0; next }
    !skipping { print }' "$doc" >"$rewritten"
  cat "$rewritten" >"$doc"
  rm -f "$rewritten"
}
