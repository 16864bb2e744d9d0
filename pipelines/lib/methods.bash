# How each rendering method of the pipelines is run: sourced by compare.sh and regions.sh, so a new tool
# plugs in here once. Needs $bin (the tools) and $scene; extra tool options come after the arguments.
#   render_method METHOD OUT.lts SECONDS SEED [tool options...]
# Methods: pt, bdpt (lt-seed); mlt, pssmlt, mmlt (lt-mutate --space path | primary | multiplexed; mlt
# seeds itself with BDPT inside its time and takes --strategies auto: Veach's perturbations, and the
# manifold perturbation on scenes with specular chains; all with the direct split, lt-mutate's default) and
# mlt-nosplit, pssmlt-nosplit, mmlt-nosplit (the same with --direct-samples -1: the chains render every path); memlt
# (path space with the bidirectional mutation and the manifold perturbation, as Jakob & Marschner define
# MEMLT); hslt (path space with the bidirectional and half-vector mutations, the pairing of Kaplanyan et al.
# 2014); mlt-lens and portal (Otsu et al.'s baseline and method: bidirectional : lens = 1 : 1, and
# bidirectional : (lens : portal = 1 : 1) = 1 : 1); gpt, gdpr (lt-gradient --method gpt | gdpr, then
# lt-reconstruct --norm l2, the unbiased one, every snapshot reconstructed) and gpt-l1, gdpr-l1 (the same
# with --norm l1); the gradient buffer is kept beside the image as gpt.gradient.lts or gdpr.gradient.lts; mlt-gd
# and gdmlt (gradient-domain MLT: lt-mutate --stream - | lt-gradient --from-paths -, the chains targeting luminance
# or the gradients, then L2; -l1 with L1), the chains' own image kept as mlt-gd.chains.lts or gdmlt.chains.lts.
# Unknown methods are refused by name.
known_methods="pt bdpt mlt pssmlt mmlt mlt-nosplit pssmlt-nosplit mmlt-nosplit memlt hslt mlt-lens portal gpt gdpr gpt-l1 gdpr-l1 mlt-gd gdmlt mlt-gd-l1 gdmlt-l1"

render_method() {
  local method="$1" file="$2" time="$3" seed="$4"; shift 4
  case "$method" in
    pt|bdpt) "$bin/lt-seed" "$scene" --method "$method" --time "$time" --seed "$seed" --snapshots doubling -o "$file" -q "$@" ;;
    mlt|pssmlt|mmlt|mlt-nosplit|pssmlt-nosplit|mmlt-nosplit)
      local space=path split=16
      case "$method" in pssmlt*) space=primary ;; mmlt*) space=multiplexed ;; esac
      case "$method" in *-nosplit) split=-1 ;; esac
      "$bin/lt-mutate" "$scene" --space "$space" --direct-samples "$split" --time "$time" --seed "$seed" \
        --snapshots doubling -o "$file" -q "$@" ;;
    memlt)
      "$bin/lt-mutate" "$scene" --strategies bidirectional,manifold --time "$time" --seed "$seed" --snapshots doubling \
        -o "$file" -q "$@" ;;
    hslt)
      "$bin/lt-mutate" "$scene" --strategies bidirectional,hslt --time "$time" --seed "$seed" --snapshots doubling \
        -o "$file" -q "$@" ;;
    mlt-lens)
      "$bin/lt-mutate" "$scene" --strategies bidirectional,lens --time "$time" --seed "$seed" --snapshots doubling \
        -o "$file" -q "$@" ;;
    portal)
      "$bin/lt-mutate" "$scene" --strategies bidirectional:2,lens,portal --time "$time" --seed "$seed" \
        --snapshots doubling -o "$file" -q "$@" ;;
    gpt|gdpr|gpt-l1|gdpr-l1|mlt-gd|gdmlt|mlt-gd-l1|gdmlt-l1)
      # One render per estimator and comparison: gpt and gpt-l1 of one run of compare.sh (which touches
      # OUT/.started first) reconstruct the same gradient buffer, each charged its own reconstruction.
      local estimator="${method%-l1}" norm=l2 dir; dir="$(dirname "$file")"
      local gradient="$dir/$estimator.gradient.lts"
      [ "$estimator" != "$method" ] && norm=l1
      if ! { [ -f "$dir/.started" ] && [ "$gradient" -nt "$dir/.started" ]; }; then
        case "$estimator" in
          gpt|gdpr)
            "$bin/lt-gradient" "$scene" --method "$estimator" --time "$time" --seed "$seed" --snapshots doubling \
              -o "$gradient" -q "$@" ;;
          *)
            # The two stages side by side in a pipe: the snapshots' times are the pipeline's.
            local target=luminance; [ "$estimator" = gdmlt ] && target=gradient
            "$bin/lt-mutate" "$scene" --target "$target" --time "$time" --seed "$seed" --stream - \
              -o "$dir/$estimator.chains.lts" -q "$@" |
              "$bin/lt-gradient" "$scene" --from-paths - --snapshots doubling -o "$gradient" -q "$@" ;;
        esac
      fi
      "$bin/lt-reconstruct" "$gradient" --norm "$norm" -o "$file" -q ;;
    *) echo "$0: unknown method '$method' (known: $known_methods)" >&2; return 1 ;;
  esac
}

# Refuse unknown methods before spending any time rendering.
check_methods() {
  local m
  for m in "$@"; do
    case " $known_methods " in *" $m "*) ;; *) render_method "$m" /dev/null 0 0 || return 1 ;; esac
  done
}
