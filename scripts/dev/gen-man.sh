#!/usr/bin/env bash
# gen-man.sh SUNMC - write the sunmc(1) man page on stdout, built from the
# binary's own --help texts (commands, options, every family's config keys),
# so the page says what --help says.  `make man` writes man/sunmc.1 with it;
# tests/cli/test_help_man.c checks that the checked-in page is in step.
set -eu
bin=${1:?usage: gen-man.sh SUNMC}
# Escape troff: backslashes, and a leading '.' or '\'' on a line.
esc() { sed -e 's/\\/\\e/g' -e "s/^\\./\\\\\\&./" -e "s/^'/\\\\\\&'/"; }
block() { printf '.nf\n'; esc; printf '.fi\n'; }
version=$("$bin" --version | awk 'NR == 1 {print $2}')
commands=$("$bin" --help | sed -n '/^usage:/,/^$/p' | awk 'NR > 1 && NF { print $1 }')
families=$("$bin" --help | sed -n 's/.*--family \([a-z|]*\)$/\1/p' | head -1 | tr '|' ' ')
cat <<HEAD
.TH SUNMC 1 "" "sunmc $version" "User Commands"
.SH NAME
sunmc \\- Monte Carlo tolerance, calibration and design trades for satellite sun sensors
.SH SYNOPSIS
.B sunmc
.I COMMAND
[\\fIoptions\\fR]
.SH DESCRIPTION
sunmc simulates thousands of sun sensors built with given manufacturing and
assembly tolerances, calibrates each one on a simulated turntable, validates it
on angles it was not calibrated on, and reports how accurate they are, how many
meet the spec, and which tolerance or calibration choice to change.  The same
fitting code calibrates a real sensor from a lab's turntable data.
.PP
The overview, as \\fBsunmc \\-\\-help\\fR prints it:
.PP
HEAD
"$bin" --help | sed -n '1,/^$/d; /^config keys of/,$d; p' | block
echo '.SH COMMANDS'
for c in $commands; do
  printf '.SS %s\n' "$c"
  "$bin" "$c" --help | block
done
echo '.SH CONFIGURATION KEYS'
echo 'Each family'"'"'s keys with their defaults and units; \fBsunmc config \-\-reference\fR'
echo 'explains each key and its allowed range.'
for f in $families; do
  printf '.SS %s\n' "$f"
  "$bin" --help --family "$f" | sed -n '/^config keys of/,$p' | block
done
cat <<'TAIL'
.SH EXIT STATUS
0 on success; 2 for bad input (a wrong option, config key or value, or data
file, with FILE:LINE where there is one; nothing is written); 1 for any other
failure (a result sunmc refuses to stand behind, or an output it cannot write).
.SH FILES
Shipped configs and gnuplot scripts are installed under
\fIPREFIX/share/sunmc/\fR.  Output files are tab-separated with a header line.
.SH SEE ALSO
\fBgnuplot\fR(1); the README of the sunmc source tree.
TAIL
