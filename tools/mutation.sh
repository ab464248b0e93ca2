#!/usr/bin/env bash
# Mutation testing of puppet/physics, puppet/interface, puppet/timeline (and puppet/mocap)
# with mutmut, on a seeded sample of mutants. Not part of CI. See docs/mutation.md.
#
#   tools/mutation.sh [SAMPLE [SEED [BUDGET]]]   defaults: 60 mutants, seed 17, 60 min
#
# Runs in a scratch copy of the tree (MUTATION_DIR, default /tmp/puppet-mutation), one
# test process at a time; the report goes to MUTATION_DIR/report.txt. BUDGET: minutes
# for running the sample once the mutants are made and the tests' reach recorded (0: no
# limit); the mutants not reached by then are reported as not run.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
sample="${1:-60}"
seed="${2:-17}"
budget="${3:-60}"
work="${MUTATION_DIR:-/tmp/puppet-mutation}"
python="${PYTHON:-$here/.venv/bin/python}"
mutmut="$(dirname "$python")/mutmut"
[ -x "$mutmut" ] || { echo "mutation.sh: mutmut is not installed: $(dirname "$python")/pip install 'mutmut==3.8.1'" >&2; exit 2; }
if "$python" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))'; then
    echo "mutation.sh: note: under Python 3.11.7 mutmut's stats run crashed the interpreter;" \
         "use a 3.12 venv (PYTHON=..., docs/mutation.md)" >&2
fi
rm -rf "$work"
mkdir -p "$work"
(cd "$here" && git ls-files -co --exclude-standard -z \
    | xargs -0 cp --parents -t "$work")
cp "$here/tools/mutation.cfg" "$work/setup.cfg"
cd "$work"
export SDL_VIDEODRIVER=dummy SDL_AUDIODRIVER=dummy PYGAME_HIDE_SUPPORT_PROMPT=1
export PUPPET_FUZZ_CASE_SECONDS=30  # a fuzz case's hang bound, under the trampolines
exec "$python" "$here/tools/mutation_sample.py" --mutmut "$mutmut" --sample "$sample" --seed "$seed" --budget "$budget"
