#!/bin/sh
# Fails if the shared library exports any symbol outside the hgcd_ prefix, or
# fewer than the second argument (default 21) of them.
lib=$1
bad=$(nm -D --defined-only "$lib" | awk '$2 ~ /^[TDBRVW]$/ {print $3}' | grep -v '^hgcd_' | grep -v '^HGCD_')
if [ -n "$bad" ]; then echo "exported outside hgcd_*:"; echo "$bad"; exit 1; fi
count=$(nm -D --defined-only "$lib" | grep -c ' hgcd_')
echo "$count hgcd_* symbols exported, nothing else"
[ "$count" -gt "${2:-20}" ]
