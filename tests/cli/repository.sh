#!/usr/bin/env bash
# The repository as a whole: it stands alone (no file refers to documents or data outside it, the scenes
# the tests and the README use are in scenes/), and libpath's includes point down its layers
# (libpath/README.md draws them).
#   repository.sh BIN_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash" "$@"
cd "$src" || exit 1

# The names are split so that this file does not match itself.
outside="\.\./shar""ed|/work/shar""ed|ALGORITHMS""\.md|DESIGN""\.md|STYLE""\.md"
files() { if git rev-parse --is-inside-work-tree > /dev/null 2>&1; then git ls-files; else find . -type f -not -path './build*'; fi; }
check "no file refers to a document or data outside the repository" \
  '! files | grep -v -E "\.(exr|png|obj|ply|serialized|lt[spb])$" | xargs grep -n -I -E "$outside" 2> /dev/null'
check "the three public scenes are in scenes/ with their licences and references" \
  'for s in cornell-box veach-mis veach-bidir; do [ -f scenes/$s/scene.xml ] && [ -f scenes/$s/LICENSE.txt ] && [ -f scenes/$s/reference.exr ] || exit 1; done'

# Layer ranks, bottom to top; a folder may include its own rank or below. formats/ (the file format)
# needs only math/ (lt::Error) and is needed by any layer.
declare -A rank=([math]=0 [texture]=1 [bsdf]=2 [scene]=3 [path]=4 [image]=5 [sampling]=6
                 [manifold]=7 [reconstruct]=7 [gradient]=7 [mcmc]=8)
layers_ok() {
  local ok=0 f dir inc
  while IFS=: read -r f inc; do
    dir="${f#libpath/}"; dir="${dir%%/*}"
    inc="${inc#*\"}"; inc="${inc%%/*}"
    [ -n "${rank[$dir]:-}" ] || { echo "  $f: folder $dir has no layer (add it to libpath/README.md and here)"; ok=1; continue; }
    [ "$inc" = formats ] && continue
    [ -n "${rank[$inc]:-}" ] || continue
    if [ "${rank[$inc]}" -gt "${rank[$dir]}" ] || { [ "${rank[$inc]}" -eq "${rank[$dir]}" ] && [ "$inc" != "$dir" ]; }; then
      echo "  $f includes $inc/: an upward or sideways include"; ok=1
    fi
  done < <(grep -rHo -E '^#include "[a-z_]+/' libpath --include='*.h' --include='*.cpp')
  if grep -rH -E '^#include "[a-z_]+/' formats --include='*.h' --include='*.cpp' | grep -v -E '"(formats|math)/'; then
    echo "  formats/ includes more of libpath than math/"; ok=1
  fi
  return $ok
}
check "libpath's includes point down its layers" layers_ok
exit $fail
