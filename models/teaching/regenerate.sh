#!/bin/sh
# Regenerates every figure and every printed output that README.md shows, from the models,
# scenarios and answers in this folder, with the project's own commands. Run from anywhere:
#
#     models/teaching/regenerate.sh
#
# The commands are the lines of commands.txt (tests/teaching.rs runs the same lines and
# fails where a committed figure is stale). Any command that fails, or ends with another
# exit code than its line says, stops the script with its error and leaves figures/ as it
# was: the new figures are written to a folder of their own and replace the old ones only
# when every command has succeeded.
#
# BONDGRAPH names the program (default: the release build of this checkout, built first).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
if [ -z "${BONDGRAPH:-}" ]; then
    (cd "$root" && cargo build --release --quiet)
    BONDGRAPH="$root/target/release/bondgraph"
fi
cd "$here"
new="$here/.figures.$$"
rm -rf "$new"
mkdir "$new"
trap 'rm -rf "$new"' EXIT
set -f # arguments are words; no globbing

count=0
while read -r file code arguments; do
    case "$file" in '' | '#'*) continue ;; esac
    set --
    for argument in $arguments; do
        case "$argument" in
            @*) set -- "$@" "$new/${argument#@}" ;;
            *) set -- "$@" "$argument" ;;
        esac
    done
    status=0
    "$BONDGRAPH" "$@" > "$new/$file" 2> "$new/.stderr" || status=$?
    if [ "$status" != "$code" ]; then
        echo "regenerate.sh: bondgraph $arguments: exit $status, expected $code" >&2
        cat "$new/.stderr" >&2
        exit 1
    fi
    count=$((count + 1))
done < commands.txt
rm -f "$new/.stderr"

rm -rf figures
mv "$new" figures
trap - EXIT
echo "regenerated $(ls figures | wc -l) files from $count commands in models/teaching/figures/"
