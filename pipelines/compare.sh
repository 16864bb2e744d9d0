#!/usr/bin/env bash
# Equal-time comparison of rendering methods on one scene, in the papers' style: every method runs for
# the same time with snapshots; the folder receives each method's image, the error-versus-time plot and
# CSV against a reference, and a figure of the images side by side (full frame and an optional crop).
#   pipelines/compare.sh SCENE --time SECONDS --methods "pt bdpt" [--ref REF.exr] [--crop X,Y,W,H]
#                        [--out DIR] [-- options for every tool, e.g. --resolution 320x240 --threads 2]
# Methods: pipelines/lib/methods.bash (pt, bdpt, mlt, pssmlt, mmlt, mlt-nosplit, pssmlt-nosplit, mmlt-nosplit, memlt,
# hslt, mlt-lens, portal, gpt, gdpr, gpt-l1, gdpr-l1, mlt-gd, gdmlt, mlt-gd-l1, gdmlt-l1).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${BUILD_DIR:-$root/build}/bin"
usage() { echo "usage: $0 SCENE --time SECONDS --methods \"pt bdpt mlt pssmlt mmlt mlt-nosplit pssmlt-nosplit mmlt-nosplit memlt hslt mlt-lens portal gpt gdpr gpt-l1 gdpr-l1 mlt-gd gdmlt mlt-gd-l1 gdmlt-l1\" [--ref REF.exr] [--crop X,Y,W,H] [--out DIR] [-- tool options]" >&2; exit 2; }
[ $# -ge 1 ] || usage
scene="$1"; shift
time=""; methods=""; ref=""; crop=""; out=""; extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --time) time="$2"; shift 2 ;;
    --methods) methods="$2"; shift 2 ;;
    --ref) ref="$2"; shift 2 ;;
    --crop) crop="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) usage ;;
  esac
done
[ -n "$time" ] && [ -n "$methods" ] || usage
[ -f "$scene" ] || { echo "$0: $scene: no such scene" >&2; exit 1; }
out="${out:-compare-$(basename "$(dirname "$scene")")}"
mkdir -p "$out"
touch "$out/.started"

source "$root/pipelines/lib/methods.bash"
check_methods $methods || exit 1

files=()
for m in $methods; do
  echo "== $m for $time s"
  render_method "$m" "$out/$m.lts" "$time" 0 "${extra[@]}"
  "$bin/lt-image" "$out/$m.lts" -o "$out/$m.exr" --png "$out/$m.png"
  files+=("$out/$m.lts")
done

if [ -n "$ref" ]; then
  cropArgs=(); [ -n "$crop" ] && cropArgs=(--crop "$crop")
  "$bin/lt-error" "${files[@]}" --ref "$ref" "${cropArgs[@]}" --csv "$out/error.csv" --plot "$out/error.png" | tee "$out/error.txt"
fi

# The figure: the methods side by side, with the crop enlarged below when one is given.
/usr/bin/python3 - "$out" "$crop" $methods <<'PY'
import sys, os
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import matplotlib.image as mpimg
out, crop, methods = sys.argv[1], sys.argv[2], sys.argv[3:]
rows = 2 if crop else 1
fig, axes = plt.subplots(rows, len(methods), figsize=(4 * len(methods), 4 * rows), squeeze=False)
for i, m in enumerate(methods):
    img = mpimg.imread(os.path.join(out, m + ".png"))
    axes[0][i].imshow(img); axes[0][i].set_title(m); axes[0][i].axis("off")
    if crop:
        x, y, w, h = (int(v) for v in crop.split(","))
        axes[0][i].add_patch(plt.Rectangle((x, y), w, h, fill=False, color="yellow", linewidth=1))
        axes[1][i].imshow(img[y:y + h, x:x + w], interpolation="nearest"); axes[1][i].axis("off")
fig.tight_layout()
tmp = os.path.join(out, ".figure.partial.png")
fig.savefig(tmp, dpi=150); os.replace(tmp, os.path.join(out, "figure.png"))
PY
echo "results in $out/: figure.png, <method>.exr/.png$( [ -n "$ref" ] && echo ", error.png, error.csv, error.txt")"
