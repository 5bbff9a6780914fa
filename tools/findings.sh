#!/usr/bin/env bash
# The studies' findings, as their commands report them at this commit: runs each study into a
# scratch folder and copies its generated report.md into docs/findings/<study>.md under a first
# line naming the command and the commit that made it (nothing in those files is typed by
# hand), then puts the main job's claims table into README.md (tools/readme_findings.py).
#
#   bash tools/findings.sh                   the quick studies (see STUDIES below)
#   bash tools/findings.sh --design          and the design study (over an hour on 2 cores)
#   bash tools/findings.sh --only paper,car  just these
#   bash tools/findings.sh --no_verify       the main job without accuracy on demand (say so:
#                                            its report then gives no numerical error)
#
# Environment: PYTHON (default .venv/bin/python), SCRATCH (default a new temporary folder; its
# runs are kept there). The commands run from a clone of this checkout's commit in
# SCRATCH/src (PYTHONPATH), so the code that runs is the commit the files name, whatever is
# edited here meanwhile (the sweeps refuse a worker whose code differs from the parent's);
# uncommitted changes are not in the run (a warning says so). A study that fails stops the
# script; the files of those before it are already written.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
PYTHON=${PYTHON:-$ROOT/.venv/bin/python}
SCRATCH=${SCRATCH:-$(mktemp -d /tmp/drake_car_findings.XXXXXX)}
SCRATCH=$(cd "$(dirname "$SCRATCH")" && pwd)/$(basename "$SCRATCH")
STUDIES="paper paper_bmw handling strut_rig ride car_checks"
PAPER_VERIFY=""
while [ $# -gt 0 ]; do
  case "$1" in
    --design) STUDIES="$STUDIES design" ;;
    --only) STUDIES=${2//,/ }; shift ;;
    --no_verify) PAPER_VERIFY="--no_verify" ;;
    -h|--help) awk 'NR > 1 && !/^#/ {exit} NR > 1 {print}' "$0"; exit 0 ;;
    *) echo "findings.sh: unknown option $1 (allowed: --design, --only LIST, --no_verify)" >&2
       exit 2 ;;
  esac
  shift
done

# The code that runs: this checkout's commit, cloned (nothing uncommitted).
COMMIT=$(git rev-parse --short=7 HEAD)
if [ -n "$(git status --porcelain --untracked-files=no)" ]; then
  echo "findings.sh: WARNING: uncommitted changes here are not in the run (commit $COMMIT is)" >&2
fi
DATE=$(date -u +%Y-%m-%d)
mkdir -p docs/findings "$SCRATCH"
SRC=$SCRATCH/src
rm -rf "$SRC"
git clone -q --no-checkout "$ROOT" "$SRC"
git -C "$SRC" checkout -q --detach "$(git rev-parse HEAD)"

# study -> the command's arguments (its module is drake_car.commands.<command>)
args_of() {
  case "$1" in
    paper)      echo "paper --out $SCRATCH/paper --no_html $PAPER_VERIFY" ;;
    paper_bmw)  echo "paper --out $SCRATCH/paper_bmw --no_html $PAPER_VERIFY --scene_text 'car_file: cars/bmw_320i.yaml'" ;;
    handling)   echo "handling --out $SCRATCH/handling" ;;
    strut_rig)  echo "strut_rig --out $SCRATCH/strut_rig" ;;
    ride)       echo "ride --out $SCRATCH/ride --classes B --speeds 60" ;;
    car_checks) echo "car_checks --out $SCRATCH/car_checks" ;;
    design)     echo "design --out $SCRATCH/design" ;;
    *) echo "findings.sh: no study $1 (paper, paper_bmw, handling, strut_rig, ride, car_checks, design)" >&2
       return 2 ;;
  esac
}

for study in $STUDIES; do
  args=$(args_of "$study")
  eval "set -- $args"  # the arguments as quoted above
  command=$1; shift
  folder=$study
  script="drake-car-${command//_/-}"
  shown="$script$(printf ' %q' "$@")"  # the arguments as a shell takes them back
  echo "findings: $shown ..." >&2
  start=$(date +%s)
  (cd "$SRC" && PYTHONPATH=$SRC "$PYTHON" -m "drake_car.commands.$command" "$@" --quiet)
  wall=$(( $(date +%s) - start ))
  # The report as the command wrote it; its links to the output folder's files (figures,
  # CSVs) become names in code type: the files stay in the scratch folder, not in docs/.
  {
    echo "Made by \`$shown\` at commit $COMMIT ($DATE, ${wall} s of wall; tools/findings.sh copied its report.md here, links to its output files shown as names)."
    echo
    sed -E -e 's/!?\[([^]]*)\]\(([^): ]+\.(png|svg|html|csv|json|txt))\)/`\2`/g' \
      -e "s#$SRC/##g" "$SCRATCH/$folder/report.md"
  } > "docs/findings/$study.md"
  echo "findings: wrote docs/findings/$study.md (${wall} s of wall; runs in $SCRATCH/$folder)" >&2
done

for study in paper paper_bmw; do
  if [ -f "docs/findings/$study.md" ]; then
    PYTHONPATH=$ROOT "$PYTHON" tools/readme_findings.py "docs/findings/$study.md" README.md \
      "findings:$study"
  fi
done
echo "findings: scratch folder $SCRATCH" >&2
