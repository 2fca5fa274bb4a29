#!/usr/bin/env bash
# Seeds each fuzz target's corpus from the repository's own files (models/, tests/fixtures/).
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p fuzz/corpus/{model,analyze,scenario,extension,csv,compare,experiment}
find models tests/fixtures -name '*.ron' ! -path '*/scenarios/*' ! -path '*/extensions/*' \
    ! -path '*/answers/*' ! -name 'experiment*.ron' ! -name 'fig6.ron' \
    -exec cp --backup=numbered -t fuzz/corpus/model {} +
cp fuzz/corpus/model/* fuzz/corpus/analyze/
find models -path '*/scenarios/*' -name '*.ron' -exec cp --backup=numbered -t fuzz/corpus/scenario {} +
cp models/eversion/fig6.ron fuzz/corpus/scenario/
find models -path '*/extensions/*' -name '*.ron' -exec cp --backup=numbered -t fuzz/corpus/extension {} +
find models tests -name '*.csv' -exec cp --backup=numbered -t fuzz/corpus/csv {} +
find models/teaching/answers tests/fixtures/analysis -name '*.ron' \
    -exec cp --backup=numbered -t fuzz/corpus/compare {} +
# An experiment's seed is its text, a line `---`, then a CSV of its folder.
n=0
for experiment in $(find models -name 'experiment*.ron'); do
    for csv in $(find "$(dirname "$experiment")" -name '*.csv' | head -n 3); do
        n=$((n + 1))
        { cat "$experiment"; printf '\n---\n'; head -n 40 "$csv"; } > "fuzz/corpus/experiment/seed_$n"
    done
done
for d in model analyze scenario extension csv compare experiment; do
    echo "$d: $(ls fuzz/corpus/$d | wc -l) seeds"
done
