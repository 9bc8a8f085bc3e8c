# Command-line handling shared by the bash scripts (sourced, not run): one option table per
# script both parses the arguments and prints --help, so the help cannot drift from the parser;
# errors print as "PROGRAM: error: message"; an unknown option names the nearest known one.
#
# A script sets, then calls cli_parse "$@":
#   CLI_PROG=run                           its name, as in errors
#   CLI_USAGE='SCENARIO [options]'          what follows "Usage: PROGRAM" (lines: several usages)
#   CLI_ABOUT='what it does'                printed after the usage, wrapped
#   CLI_POS_HELP='SCENARIO|paper, ...'      METAVAR|HELP of the positional arguments; empty: none
#   CLI_EPILOG='...'                        printed after the options (optional)
#   CLI_OPTS=(                              one entry per option: NAME|VAR|METAVAR|HELP|DEFAULT
#     '--realizations|N|N|ensemble size|500'   a value: VAR=value
#     '--set|SETS+|key=value|override a key|'  VAR ending in +: each value appended to array VAR
#     '--realtime|REALTIME||pace it|'          no METAVAR: a flag, VAR=1
#   )                                          (no '|' inside a field; HELP '-' hides an entry,
#                                              VAR starting with @: NAME and value appended to
#                                              that array, to pass them on to another program)
# cli_parse handles -h/--help (usage on stdout, exit 0), --list-options (each NAME [METAVAR],
# exit 0), NAME VALUE and NAME=VALUE; positional arguments land in the array CLI_POS.
# A script that passes its arguments on (scripts/test, scripts/sanitize: to ctest) has no table:
# it sets CLI_PASS_THROUGH=1 and calls cli_help itself for -h/--help.

CLI_WIDTH=100   # help is wrapped at this many columns
CLI_COLUMN=26   # option descriptions start in this column

# "PROGRAM: error: message" on stderr, exit status 2 (bad input).
cli_die() {
  echo "${CLI_PROG:-${0##*/}}: error: $*" >&2
  exit 2
}

# The candidate nearest to WORD by edit distance if it is close enough, nothing otherwise: the
# Python package's rule (scripts/rnav/cli_args.py `closest`, the same as common/io/did_you_mean.hpp),
# called rather than written again. Debian's /usr/bin/python3 (the project's, as every Python
# program in scripts/ names it) when there is one, as it starts at once; else any python3 (numpy
# is not needed). A python3 found on PATH may be a version manager's shim that takes a third of
# a second to start: every misspelt option waited for it.
CLI_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
CLI_PYTHON=python3
[[ -x /usr/bin/python3 ]] && CLI_PYTHON=/usr/bin/python3
cli_closest() {
  local word=$1; shift
  (($#)) || return 0
  PYTHONPATH="$CLI_DIR${PYTHONPATH:+:$PYTHONPATH}" "$CLI_PYTHON" -c '
import sys
from rnav.cli_args import closest
c = closest(sys.argv[1], sys.argv[2:])
if c:
    print(c)' "$word" "$@"
}

# " (did you mean 'X'?)" for the nearest candidate, or nothing.
cli_did_you_mean() {
  local c
  c=$(cli_closest "$@")
  [[ -n $c ]] && printf " (did you mean '%s'?)" "$c"
  return 0
}

# The help text from records on stdin, one per line, tab-separated: "L<TAB>line" printed as is;
# "P<TAB>text" a paragraph wrapped at CLI_WIDTH; "E<TAB>left<TAB>text" an entry "  left" with
# text wrapped under CLI_COLUMN (on the next line when left does not leave two spaces). One awk
# for the whole help: a process per entry made --help take a fifth of a second.
cli_format() {
  awk -F '\t' -v width="$CLI_WIDTH" -v column="$CLI_COLUMN" '
    # the words of text wrapped, continuation lines indented by indent, the first starting at col
    function wrap(text, indent, col,    n, w, i, empty, pad) {
      n = split(text, w, /[ \t\n]+/); empty = 1; pad = sprintf("%" indent "s", "")
      for (i = 1; i <= n; i++) {
        if (w[i] == "") continue
        if (!empty && col + 1 + length(w[i]) > width) { printf "\n%s", pad; col = indent; empty = 1 }
        if (!empty) { printf " "; col++ }
        printf "%s", w[i]; col += length(w[i]); empty = 0
      }
      printf "\n"
    }
    $1 == "L" { print substr($0, 3); next }
    $1 == "P" { wrap(substr($0, 3), 0, 0); next }
    $1 == "E" {
      left = "  " $2
      if (length(left) + 2 > column) printf "%s\n%" column "s", left, ""
      else printf "%s%" (column - length(left)) "s", left, ""
      wrap($3, column, column)
    }'
}

# Fields of option entry $1 into the globals O_NAME O_VAR O_META O_HELP O_DEF (or die: a
# developer's error, caught by the help test).
cli_fields() {
  local rest
  IFS='|' read -r O_NAME O_VAR O_META O_HELP O_DEF rest <<<"$1"
  [[ -z $rest && -n $O_NAME && -n $O_VAR ]] || cli_die "internal: bad option table entry '$1'"
}

cli_help() {
  local first=1 line e text
  # every entry checked here, in this shell: inside the pipe below cli_die would end only the pipe's subshell
  for e in "${CLI_OPTS[@]}"; do cli_fields "$e"; done
  {
    while IFS= read -r line; do
      if ((first)); then printf 'L\tUsage: %s\n' "$CLI_PROG${line:+ $line}"; first=0; else printf 'L\t       %s\n' "$CLI_PROG${line:+ $line}"; fi
    done <<<"${CLI_USAGE:-}"
    if [[ -n ${CLI_ABOUT:-} ]]; then printf 'L\t\nP\t%s\n' "${CLI_ABOUT//$'\n'/ }"; fi
    if [[ -n ${CLI_POS_HELP:-} ]]; then
      printf 'L\t\nL\tArguments:\n'
      text=${CLI_POS_HELP#*|}
      printf 'E\t%s\t%s\n' "${CLI_POS_HELP%%|*}" "${text//$'\n'/ }"
    fi
    printf 'L\t\nL\tOptions:\n'
    for e in "${CLI_OPTS[@]}"; do
      cli_fields "$e"
      [[ $O_HELP == - ]] && continue
      text=$O_HELP
      [[ $O_VAR == *+ ]] && text+=" (repeatable)"
      if [[ $O_DEF == required ]]; then text+=" (required)"; elif [[ -n $O_DEF ]]; then text+=" (default $O_DEF)"; fi
      printf 'E\t%s\t%s\n' "$O_NAME${O_META:+ $O_META}" "${text//$'\n'/ }"
    done
    printf 'E\t%s\t%s\n' "-h, --help" "print this help and exit"
    [[ -n ${CLI_PASS_THROUGH:-} ]] || printf 'E\t%s\t%s\n' "--list-options" "print the option names, one per line, and exit"
  } | cli_format
  if [[ -n ${CLI_EPILOG:-} ]]; then echo; printf '%s\n' "$CLI_EPILOG"; fi
}

cli_list() {
  local e
  for e in "${CLI_OPTS[@]}"; do cli_fields "$e"; echo "$O_NAME${O_META:+ $O_META}"; done
  printf '%s\n' -h --help --list-options
}

cli_parse() {
  CLI_POS=()
  local a e name value found names=(--help --list-options) unknown=() errors=() hint
  for a in "$@"; do
    case $a in
      -h|--help) cli_help; exit 0 ;;
      --list-options) cli_list; exit 0 ;;
    esac
  done
  for e in "${CLI_OPTS[@]}"; do cli_fields "$e"; names+=("$O_NAME"); done
  # Every unknown option and every malformed one is collected and named in one error at the end.
  while (($#)); do
    a=$1; shift
    if [[ $a != -?* || $a == -[0-9]* ]]; then
      [[ -n ${CLI_POS_HELP:-} ]] || { errors+=("unexpected argument '$a' (see $CLI_PROG --help)"); continue; }
      CLI_POS+=("$a"); continue
    fi
    name=${a%%=*} found=""
    for e in "${CLI_OPTS[@]}"; do
      cli_fields "$e"
      [[ $O_NAME == "$name" ]] && { found=1; break; }
    done
    if [[ -z $found ]]; then
      hint=$(cli_did_you_mean "$name" "${names[@]}")
      unknown+=("'$a'$hint"); continue
    fi
    if [[ -z $O_META ]]; then
      [[ $a == *=* ]] && { errors+=("option $name takes no value, got '$a'"); continue; }
      value=1
    elif [[ $a == *=* ]]; then
      value=${a#*=}
    else
      (($#)) || { errors+=("option $name needs a value ($O_META)"); continue; }
      value=$1; shift
    fi
    case $O_VAR in
      @*) local -n cli_ref=${O_VAR#@}; cli_ref+=("$name"); [[ -n $O_META ]] && cli_ref+=("$value"); unset -n cli_ref ;;
      *+) local -n cli_ref=${O_VAR%+}; cli_ref+=("$value"); unset -n cli_ref ;;
      *) printf -v "$O_VAR" '%s' "$value" ;;
    esac
  done
  cli_parse_errors
}

# The errors cli_parse collected (arrays unknown, errors), one line naming them all, or nothing.
# A word an unknown option is followed by may be its value: "unexpected argument" is left out then.
cli_parse_errors() {
  local msg="" u all
  if ((${#unknown[@]})); then
    ((${#unknown[@]} == 1)) && msg="unknown option " || msg="unknown options "
    all=$(printf "%s, " "${unknown[@]}"); msg+=${all%, }
    for u in "${unknown[@]}"; do [[ $u == *"did you mean"* ]] || { msg+=" (see $CLI_PROG --help)"; break; }; done
    local kept=()
    for u in "${errors[@]}"; do [[ $u == "unexpected argument "* ]] || kept+=("$u"); done
    errors=("${kept[@]}")
  fi
  for u in "${errors[@]}"; do msg+="${msg:+; }$u"; done
  [[ -z $msg ]] || cli_die "$msg"
}
