#!/usr/bin/env bash
# seam on real tows: at least twelve interpenetrating configurations made from the CT-scanned tows
# of ../shared/data/polytex, each run through `seam pair`, `seam check` and `tetgen -d` (see
# scripts/real_tows.py for the configurations and the columns). Builds seam first; skips cleanly
# when the data is absent.
#   scripts/real_tows.sh [--only 1,4,9] [--markdown docs/real_tows.md] [-- seam pair options]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
data="${SEAM_POLYTEX:-../shared/data/polytex}"
if [[ ! -f "$data/profile_0_weft.stl" || ! -f "$data/profile_51_binder.stl" ]]; then
  echo "real_tows: no CT tows in $data: skipped"
  exit 0
fi
bash scripts/build.sh > /dev/null
exec /usr/bin/python3 scripts/real_tows.py --data "$data" "$@"
