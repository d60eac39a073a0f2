# help.sh -- `--help` for the project's shell scripts: prints the script's header comment
# (the lines after the shebang up to the first line that is not a comment).
#   source "$(dirname "$0")/lib/help.sh"; help_if_asked "$0" "$@"
help_if_asked() {
  local self=$1
  shift
  case ${1:-} in
    -h|--help) sed -n '2,/^[^#]/{/^#/{s/^# \{0,1\}//;p;};}' "$self"; exit 0 ;;
  esac
}
