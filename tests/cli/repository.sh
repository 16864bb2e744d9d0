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

# Layer ranks, bottom to top; a folder may include its own folder or a lower rank, never a sibling of its own rank
# (mcmc/ and gradient/ are siblings: gradient-domain MLT, which needs both, is gdmlt/ above them). formats/ (the file
# format) needs only util/ (lt::Error, temporary outputs) and is needed by any layer.
declare -A rank=([util]=0 [math]=1 [texture]=2 [bsdf]=3 [scene]=4 [path]=5 [image]=6 [sampling]=7
                 [manifold]=8 [reconstruct]=8 [gradient]=9 [mcmc]=9 [gdmlt]=10 [run]=11)
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
  if grep -rH -E '^#include "[a-z_]+/' formats --include='*.h' --include='*.cpp' | grep -v -E '"(formats|util)/'; then
    echo "  formats/ includes more of libpath than util/"; ok=1
  fi
  return $ok
}
check "libpath's includes point down its layers" layers_ok
exit $fail
