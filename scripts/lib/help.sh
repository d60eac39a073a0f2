# help.sh -- `--help` and option checks for the project's shell scripts.
#   source "$(dirname "$0")/lib/help.sh"; help_if_asked "$0" "$@"
#   check_options "$0" "--runs= --quiet" "$@"     (before the script starts anything)
# help_if_asked prints the script's header comment (the lines after the shebang up to the first
# line that is not a comment) for -h/--help and exits 0.

# The name a script's messages start with: "hil-demo", or "bench fcc" for scripts/bench.d/fcc.
script_name() {
  case $1 in
    */bench.d/*) echo "bench $(basename "$1")" ;;
    *) basename "$1" ;;
  esac
}

help_if_asked() {
  local self=$1
  shift
  case ${1:-} in
    -h|--help) sed -n '2,/^[^#]/{/^#/{s/^# \{0,1\}//;p;};}' "$self"; exit 0 ;;
  esac
}

# One line on stderr and exit 2: a usage error.
usage_error() {
  local name; name=$(script_name "$1")
  echo "$name: $2 (see $1 --help)" >&2
  exit 2
}

# The arguments of a script that takes only options, checked before anything starts: SPEC lists
# the option names it takes, space-separated, NAME= for one with a value (--name V or
# --name=V); "" for a script that takes none.  Anything else is a usage error.  The values are
# the program's to check.
check_options() {
  local self=$1 spec=" $2 "
  shift 2
  while [ $# -gt 0 ]; do
    case $1 in
      --*=*)
        [[ $spec == *" ${1%%=*}= "* ]] || usage_error "$self" "unknown option '${1%%=*}'"
        shift ;;
      *)
        if [[ $spec == *" $1= "* ]]; then
          [ $# -ge 2 ] || usage_error "$self" "$1 needs a value"
          shift 2
        elif [[ $1 == -* && $spec == *" $1 "* ]]; then
          shift
        elif [[ $1 == -* ]]; then
          usage_error "$self" "unknown option '$1'"
        else
          usage_error "$self" "unexpected argument '$1'"
        fi ;;
    esac
  done
}
