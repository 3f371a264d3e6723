# Sourced by facet's scripts with their arguments, before anything else: with -h or --help as the
# first argument, prints the calling script's leading comment (its documentation) and exits 0.
if [ "${1:-}" = "-h" ] || [ "${1:-}" = "--help" ]; then
  sed -n '2,/^[^#]/{/^#/{s/^# \{0,1\}//;p}}' "$0"
  exit 0
fi
