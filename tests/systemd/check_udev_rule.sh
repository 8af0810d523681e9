#!/usr/bin/env bash
# The udev rule (systemd/udev/60-gportd.rules) against the adapters
# docs/operations.md names: for each vendor:product, a rule of the tty
# subsystem that matches it gives /dev/gimbal, the systemd tag, the
# ModemManager ignore flag and root:dialout 0660; the FTDI latency rule is
# there; and every rule line parses as udev's KEY op "VALUE" pairs. Where
# udevadm can verify rule files (systemd 253+: `udevadm verify`), it does too.
#
#   check_udev_rule.sh RULES_FILE
set -euo pipefail
rules=${1:?usage: check_udev_rule.sh RULES_FILE}
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

# The rule's logical lines: comments dropped, continuations joined.
logical=$(sed -e 's/^[[:space:]]*#.*$//' "$rules" | sed -e ':a' -e '/\\$/N; s/\\\n//; ta' |
  tr -s ' ' | grep -v '^[[:space:]]*$')

adapters=(
  0403:6001 0403:6010 0403:6011 0403:6014 0403:6015  # FTDI
  10c4:ea60                                          # Silicon Labs CP210x
  1a86:7523 1a86:5523 1a86:55d4                      # WCH CH340, CH341, CH9102
  067b:2303 067b:23a3 067b:23c3 067b:23d3            # Prolific PL2303, GC, GT, GL
)
for adapter in "${adapters[@]}"; do
  vendor=${adapter%%:*}
  product=${adapter#*:}
  line=$(grep -E "SUBSYSTEM==\"tty\".*ATTRS\{idVendor\}==\"$vendor\".*ATTRS\{idProduct\}==\"([0-9a-f|]*\|)?$product(\|[0-9a-f|]*)?\"" \
    <<<"$logical" || true)
  if [[ -z $line ]]; then
    fail "no tty rule matches $adapter"
    continue
  fi
  for want in 'SYMLINK+="gimbal"' 'TAG+="systemd"' 'ENV{ID_MM_DEVICE_IGNORE}="1"' \
      'GROUP="dialout"' 'MODE="0660"'; do
    grep -qF -- "$want" <<<"$line" || fail "the rule for $adapter lacks $want"
  done
done
grep -qE 'SUBSYSTEM=="usb-serial", DRIVER=="ftdi_sio", ATTR\{latency_timer\}="1"' <<<"$logical" ||
  fail "the FTDI latency timer rule is missing"

# Each logical line: comma-separated KEY op "VALUE" pairs, or a LABEL.
pair='[A-Za-z_]+(\{[A-Za-z_]+\})?[[:space:]]*(==|!=|\+=|-=|:=|=)[[:space:]]*"[^"]*"'
while IFS= read -r line; do
  [[ $line =~ ^[[:space:]]*($pair)([[:space:]]*,[[:space:]]*($pair))*[[:space:]]*$ ]] ||
    fail "not udev syntax: $line"
done <<<"$logical"

if udevadm verify --help >/dev/null 2>&1; then
  udevadm verify "$rules" || fail "udevadm verify"
fi

((failures == 0)) || exit 1
echo "PASS: ${#adapters[@]} adapters get /dev/gimbal; the rule file parses"
