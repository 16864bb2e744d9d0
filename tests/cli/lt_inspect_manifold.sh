#!/usr/bin/env bash
# lt-inspect PATHS.ltp --manifold: the specular chains of stored paths rebuilt on their scene (glass and
# mirror spheres of scenes/cornell-spheres), their generalized geometry terms, walks to themselves and
# the walk statistics; the scene named in the file and --scene; errors for a wrong scene and a buffer file.
#   lt_inspect_manifold.sh BIN_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash" "$@"

tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
scene="$src/scenes/cornell-spheres/scene.xml"
"$bin/lt-seed" "$scene" --spp 1 --resolution 32x24 --seed 1 -o "$tmp/a.lts" --paths "$tmp/a.ltp" --max-paths 200 -q
check "a render with paths to inspect" '[ -s "$tmp/a.ltp" ]'

"$bin/lt-inspect" "$tmp/a.ltp" --manifold --limit 3 > "$tmp/m.txt" 2>&1; code=$?
check "--manifold: exit 0" '[ $code -eq 0 ]'
check "--manifold: chains listed with G and walk outcomes" 'grep -Eq "^  chain vertices [0-9]+\.\.[0-9]+: G = [0-9.e+-]+, walk of the (eye|light) end to itself: converged in [0-9]+" "$tmp/m.txt"'
check "--manifold: summary line" 'grep -Eq "^paths 200, with specular chains [1-9][0-9]*, chains [1-9][0-9]* \(rebuilt [1-9][0-9]*, with an end to walk [1-9][0-9]*\), walks to themselves converged [1-9][0-9]*/[1-9][0-9]*" "$tmp/m.txt"'
# Analytic spheres: nearly every walk to a nearby point converges (ME reports 92-98 %).
check "--manifold: walk statistics, most walks converge" 'awk "/^  converged/ { gsub(/[()%]/, \"\"); exit !(\$3 >= 80) }" "$tmp/m.txt"'
check "--manifold: iterations and chain lengths" 'grep -Eq "^  iterations \(converged\) +mean [0-9.]+, max [0-9]+; per walk [0-9.]+$" "$tmp/m.txt" && grep -Eq "^  chain lengths \(vertices\) +[0-9]+: [0-9]+" "$tmp/m.txt"'
check "--manifold --scene gives the same report" '"$bin/lt-inspect" "$tmp/a.ltp" --manifold --limit 3 --scene "$scene" | cmp -s - "$tmp/m.txt"'

"$bin/lt-inspect" "$tmp/a.ltp" --manifold --scene "$src/tests/cli/tiny_box.xml" > "$tmp/e1.txt" 2>&1; code=$?
check "--manifold with another scene: one error line, non-zero exit" '[ $code -ne 0 ] && [ $(wc -l < "$tmp/e1.txt") -eq 1 ] && grep -q "hash" "$tmp/e1.txt"'
"$bin/lt-inspect" "$tmp/a.lts" --manifold > "$tmp/e2.txt" 2>&1; code=$?
check "--manifold on a buffer file: one error line, non-zero exit" '[ $code -ne 0 ] && [ $(wc -l < "$tmp/e2.txt") -eq 1 ]'
"$bin/lt-inspect" "$tmp/a.ltp" --scene "$scene" > "$tmp/e3.txt" 2>&1; code=$?
check "--scene without --manifold: error" '[ $code -ne 0 ] && grep -q "goes with --manifold" "$tmp/e3.txt"'
exit $fail
