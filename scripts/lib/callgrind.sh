# callgrind.sh -- read callgrind output files; sourced by the parts of scripts/bench.

# Inclusive instruction count of function $2 in callgrind output $1 (0 if absent).
callgrind_inclusive() {
  callgrind_annotate --inclusive=yes --threshold=100 "$1" 2>/dev/null |
    awk -v fn="$2" '!found { for (i = 1; i <= NF; ++i) if ($i ~ (":" fn "$")) { gsub(",", "", $1); n = $1; found = 1 } }
                    END { print found ? n : 0 }'
}
