#!/usr/bin/env bash
# lt-inspect from the command line: every shipped scene is described (text and valid JSON);
# bad input gives exactly one error line and a non-zero exit; --help works.
#   lt_inspect.sh BIN_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash" "$@"

scenes=("$src"/scenes/*/scene.xml)
check "nine scenes to describe" '[ ${#scenes[@]} -ge 9 ]'
for s in "${scenes[@]}"; do
  check "text summary of $s" '"$bin/lt-inspect" "$s" > /tmp/lt_inspect_out.$$ 2>&1 && grep -q "^needs" /tmp/lt_inspect_out.$$'
  check "json summary of $s" '"$bin/lt-inspect" "$s" --json | python3 -c "import json,sys; d=json.load(sys.stdin); assert d[\"kind\"]==\"scene\" and \"needs\" in d"'
done

check "--help exits 0" '"$bin/lt-inspect" --help | grep -q "lt-inspect"'

out=$("$bin/lt-inspect" /nonexistent/scene.xml 2>&1); code=$?
check "missing file: non-zero exit" '[ $code -ne 0 ]'
check "missing file: one line naming the file" '[ "$out" = "lt-inspect: error: /nonexistent/scene.xml: cannot open scene file" ]'

tmp=$(mktemp -d); trap 'rm -rf "$tmp"; rm -f /tmp/lt_inspect_out.$$' EXIT
printf '<scene version="0.5.0">\n<shape type="sphere">\n<float name="radius" value="x"/>\n</shape>\n</scene>\n' > "$tmp/bad.xml"
out=$("$bin/lt-inspect" "$tmp/bad.xml" 2>&1); code=$?
check "bad number: non-zero exit" '[ $code -ne 0 ]'
check "bad number: one line with file and line" '[ "$out" = "lt-inspect: error: $tmp/bad.xml:3: <float>: '"'"'x'"'"' is not a number" ]'

# A property lt does not read: a warning and a description (as Mitsuba renders it); --strict: one error line.
printf '<scene version="0.6.0">\n<shape type="sphere">\n<bsdf type="conductor"><float name="alpha" value="0.1"/></bsdf>\n</shape>\n</scene>\n' > "$tmp/lenient.xml"
out=$("$bin/lt-inspect" "$tmp/lenient.xml" 2>&1); code=$?
check "unread property: exit 0" '[ $code -eq 0 ]'
check "unread property: warned with file and line" 'echo "$out" | grep -q "^warning    $tmp/lenient.xml:3: <bsdf type=\"conductor\">: property '"'"'alpha'"'"' is not read by lt"'
out=$("$bin/lt-inspect" "$tmp/lenient.xml" --strict 2>&1); code=$?
check "unread property, --strict: non-zero exit" '[ $code -ne 0 ]'
check "unread property, --strict: one error line" '[ $(echo "$out" | wc -l) -eq 1 ] && echo "$out" | grep -q "^lt-inspect: error: $tmp/lenient.xml:3: "'

"$bin/lt-inspect" "$src/scenes/cornell-spheres/scene.xml" --no-such-option >/dev/null 2>&1; code=$?
check "unknown option: non-zero exit" '[ $code -ne 0 ]'
check "-D overrides a scene default" '"$bin/lt-inspect" "$src/scenes/cornell-spheres/scene.xml" -D res=64 --json | python3 -c "import json,sys; assert json.load(sys.stdin)[\"film\"][\"width\"]==64"'

exit $fail
