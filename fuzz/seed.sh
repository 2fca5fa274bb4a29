#!/usr/bin/env bash
# Seeds each fuzz target's corpus from the repository's own files (models/, tests/fixtures/).
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p fuzz/corpus/{model,scenario,extension,csv}
find models tests/fixtures -name '*.ron' ! -path '*/scenarios/*' ! -path '*/extensions/*' \
    ! -name 'experiment.ron' ! -name 'fig6.ron' -exec cp --backup=numbered -t fuzz/corpus/model {} +
find models -path '*/scenarios/*' -name '*.ron' -exec cp --backup=numbered -t fuzz/corpus/scenario {} +
cp models/eversion/fig6.ron fuzz/corpus/scenario/
find models -path '*/extensions/*' -name '*.ron' -exec cp --backup=numbered -t fuzz/corpus/extension {} +
find models tests -name '*.csv' -exec cp --backup=numbered -t fuzz/corpus/csv {} +
for d in model scenario extension csv; do echo "$d: $(ls fuzz/corpus/$d | wc -l) seeds"; done
