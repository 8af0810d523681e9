#!/usr/bin/env bash
# Fails when a folder uses a folder it may not: the allow-list is the table
# of docs/architecture.md, "Layout" (the rows after the line
# "<!-- layers: ... -->"): one row per folder, its second column the folders
# it may use besides itself ("—" for none). This script and the document
# read that one table.
#
# Checked, in every layered folder:
#   - includes: quoted or angled "gport/<part>/..." includes (<part> is the
#     folder whose include/ holds it) and relative "../" includes, resolved
#     against the including file, in *.cpp, *.hpp, *.h, *.cc and *.in;
#   - CMake links: every gport::<target> (and raw gport_<target>) named in
#     the folder's CMakeLists.txt and *.cmake files, outside comments, where
#     <target> is a library some layered folder declares (add_library or
#     gport_add_library); the target's folder must be on the list.
#   - private headers: a folder may use another's public headers only; the
#     headers under include/gport/<part>/core/ (the daemon's core, behind
#     its Api) are <part>/'s own, whatever the table allows (ipc/ may use
#     daemon/'s Api, not its core).
# Targets declared outside the layered folders are refused too (e.g.
# gport::test_fakes of tests/support), except the top-level CMakeLists.txt's
# (gport::asio, gport::version: Boost.Asio and the generated version header,
# usable anywhere); gport/version.hpp may be included anywhere. tests/,
# bench/ and fuzz/ are outside the table and not checked. The table must be
# acyclic and name only folders that are in it.
#
# Each finding names the file, the line, what it reaches and what the folder
# may use.
#
# usage: check-layering.sh [ROOT]   (ROOT: the source tree, default: this one)
set -euo pipefail
root=${1:-"$(dirname "$0")/.."}
cd "$root"
table_doc=docs/architecture.md

failures=0
fail() {
  echo "$1" >&2
  failures=$((failures + 1))
}

[[ -f $table_doc ]] || { echo "check-layering: $table_doc not found" >&2; exit 2; }

# ---- the table: folder -> the folders it may use -------------------------
declare -A allowed=()  # folder -> " a b c " (space-padded)
declare -A table_line=()
order=()
table=$(awk '
  /<!-- layers:/ { inside = 1; next }
  inside && /^\|/ { rows = 1; print NR "\t" $0; next }
  inside && rows { exit }
' "$table_doc")
[[ -n $table ]] || { echo "check-layering: no \"<!-- layers:\" table in $table_doc" >&2; exit 2; }
while IFS=$'\t' read -r number row; do
  IFS='|' read -r _ first second _ <<<"$row"
  folder=$(tr -d '` /' <<<"$first")
  [[ $folder == folder || $folder =~ ^-+$ ]] && continue  # header, separator
  [[ $folder =~ ^[a-z_]+$ ]] || { fail "$table_doc:$number: \"$first\" is not a folder"; continue; }
  uses=$(tr -d '`/' <<<"$second" | tr ',' ' ' | sed 's/—//g')
  allowed[$folder]=" $(xargs <<<"$uses") "
  table_line[$folder]=$number
  order+=("$folder")
done <<<"$table"

for folder in "${order[@]}"; do
  for used in ${allowed[$folder]}; do
    [[ -n ${allowed[$used]+x} ]] \
      || fail "$table_doc:${table_line[$folder]}: $folder/ may use \"$used\", which is not a row of the table"
  done
done

# No cycles: a depth-first walk from each folder must never come back to it.
declare -A state=()  # unset: new, 1: on the path, 2: done
walk() {
  local folder=$1 used
  state[$folder]=1
  for used in ${allowed[$folder]}; do
    [[ -n ${allowed[$used]+x} ]] || continue
    if [[ ${state[$used]:-} == 1 ]]; then
      fail "$table_doc:${table_line[$folder]}: the table has a cycle: $folder/ may use $used/, which may use $folder/ (through its list)"
    elif [[ -z ${state[$used]:-} ]]; then
      walk "$used"
    fi
  done
  state[$folder]=2
}
for folder in "${order[@]}"; do
  [[ -n ${state[$folder]:-} ]] || walk "$folder"
done

may_use() {  # folder part: true when folder may use part
  [[ $1 == "$2" || ${allowed[$1]} == *" $2 "* ]]
}
allowed_text() {
  local list
  list=$(xargs <<<"${allowed[$1]}")
  echo "${list:-nothing else}"
}

# ---- includes --------------------------------------------------------------
# (matched in bash, not by a process per line: the tree has hundreds)
include_re='^[[:space:]]*#[[:space:]]*include[[:space:]]*["<]([^">]+)[">]'
for folder in "${order[@]}"; do
  [[ -d $folder ]] || continue
  while IFS= read -r hit; do
    file=${hit%%:*}
    rest=${hit#*:}
    line=${rest%%:*}
    text=${rest#*:}
    [[ $text =~ $include_re ]] || continue
    target=${BASH_REMATCH[1]}
    case $target in
      gport/version.hpp)
        continue
        ;;
      gport/*/*)
        part=${target#gport/}
        part=${part%%/*}
        ;;
      ../*)
        resolved=$(realpath -m --relative-to=. "$(dirname "$file")/$target")
        part=${resolved%%/*}
        ;;
      *)
        continue
        ;;
    esac
    if [[ -z ${allowed[$part]+x} ]]; then
      fail "$file:$line: includes \"$target\", which reaches $part/, outside the layered folders"
    elif ! may_use "$folder" "$part"; then
      fail "$file:$line: includes \"$target\": $folder/ may not use $part/ (it may use: $(allowed_text "$folder"))"
    elif [[ $target == gport/$part/core/* && $folder != "$part" ]]; then
      fail "$file:$line: includes \"$target\": gport/$part/core/ is private to $part/ (use $part/'s public headers)"
    fi
  done < <(grep -rnE '^[[:space:]]*#[[:space:]]*include[[:space:]]*["<](gport/|\.\./)' \
             --include='*.cpp' --include='*.hpp' --include='*.h' --include='*.cc' \
             --include='*.in' "$folder" || true)
done

# ---- CMake links -----------------------------------------------------------
cmake_files() {  # the CMake files under $1, or of the whole tree without an argument
  find "${1:-.}" \( -name build -o -name .git \) -prune -o \
    \( -name CMakeLists.txt -o -name '*.cmake' \) -type f -print
}
# Which folder declares each target: gport::<alias> and the raw gport_<name>.
# One grep over every CMake file, the lines matched in bash (a sed and a grep
# per file were most of the script's time): the declarations first, then
# the aliases of raw names (add_library(gport::alias ALIAS gport_raw)).
declare -A owner=()
mapfile -t declarations < <(cmake_files | xargs grep -H 'add_library' || true)
declarer_of() {  # the folder of a CMake file; . for the top level (usable anywhere)
  local rel=${1#./}
  if [[ $rel == CMakeLists.txt ]]; then
    echo .
  else
    echo "${rel%%/*}"
  fi
}
library_re='add_library\([[:space:]]*(gport_[a-z0-9_]+)([[:space:]]+([a-z0-9_]+))?'
alias_re='add_library\([[:space:]]*gport::([a-z0-9_]+)[[:space:]]+ALIAS[[:space:]]+(gport_[a-z0-9_]+)'
for hit in "${declarations[@]}"; do
  code=${hit#*:}
  code=${code%%#*}
  if [[ $code =~ gport_$library_re ]]; then  # gport_add_library(gport_raw alias ...)
    owner[${BASH_REMATCH[1]}]=$(declarer_of "${hit%%:*}")
    owner["gport::${BASH_REMATCH[3]}"]=${owner[${BASH_REMATCH[1]}]}
  elif [[ $code =~ $library_re && ${code%%add_library*} != *gport_ ]]; then
    owner[${BASH_REMATCH[1]}]=$(declarer_of "${hit%%:*}")
  fi
done
for hit in "${declarations[@]}"; do
  code=${hit#*:}
  code=${code%%#*}
  if [[ $code =~ $alias_re ]]; then
    owner["gport::${BASH_REMATCH[1]}"]=${owner[${BASH_REMATCH[2]}]:-$(declarer_of "${hit%%:*}")}
  fi
done

for folder in "${order[@]}"; do
  [[ -d $folder ]] || continue
  while IFS= read -r file; do
    file=${file#./}
    number=0
    while IFS= read -r text || [[ -n $text ]]; do
      number=$((number + 1))
      code=${text%%#*}
      [[ $code == *gport* ]] || continue
      [[ $code =~ add_library\([[:space:]]*gport::[a-z0-9_]+[[:space:]]+ALIAS ]] && continue
      # Each gport::/gport_ name of the line once, matched in bash (a
      # grep and a sort per line made this loop most of the script's time).
      declare -A named=()
      rest=$code
      while [[ $rest =~ gport(::|_)[a-z0-9_]+ ]]; do
        name=${BASH_REMATCH[0]}
        rest=${rest#*"$name"}
        [[ -z ${named[$name]+x} ]] || continue
        named[$name]=1
        [[ -n ${owner[$name]+x} ]] || continue  # a function or variable, not a target
        part=${owner[$name]}
        [[ $part == . ]] && continue
        if [[ -z ${allowed[$part]+x} ]]; then
          fail "$file:$number: links $name, declared in $part/, outside the layered folders"
        elif ! may_use "$folder" "$part"; then
          fail "$file:$number: links $name: $folder/ may not use $part/ (it may use: $(allowed_text "$folder"))"
        fi
      done
      unset named
    done <"$file"
  done < <(cmake_files "$folder")
done

if ((failures > 0)); then
  echo "check-layering: $failures finding(s); the allow-list is the table in $table_doc, \"Layout\"" >&2
  exit 1
fi
echo "check-layering: every include and link is allowed (${#order[@]} folders, $table_doc)"
