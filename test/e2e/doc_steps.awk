# The steps a set-up document gives, one per output line, for
# quickstart_test.sh: STEP <tab> KIND <tab> TEXT <tab> COMMENT, where STEP is
# the number of the step the line belongs to (0 before the first) and KIND is
#   cmd    a command line of a ```sh block (continuation lines joined), COMMENT
#          what follows its " # " (what it prints, or a remark);
#   set    a setting the prose tells every reader to make, "Set `KEY: VALUE`"
#          with a capital S ("Set `lidar.source_ip: "192.168.1.200"`" gives
#          TEXT `lidar.source_ip: "192.168.1.200"`); a lower-case "set" is
#          for some readers only (a laptop's, say) and is not taken;
#   paste  a line of a ```yaml block (the example of what to paste);
#   watch  an inline `tumble-view --listen …` or `lcm-logger …` command.
# Only the lines from the first one matching the regular expression `from`
# to the next one matching `to` are read; a step starts at a line matching
# `step` (its first number is the step's number).
#   awk -v from='^## Quick start' -v to='^## ' -v step='^\\*\\*[0-9]+\\. ' -f doc_steps.awk README.md
function emit(kind, text, comment) {
  printf "%d\t%s\t%s\t%s\n", number, kind, text, comment
}
function emit_command(line,    at, comment) {
  comment = ""
  if (match(line, /[ \t]+# /)) {
    comment = substr(line, RSTART + RLENGTH)
    line = substr(line, 1, RSTART - 1)
  }
  sub(/[ \t]+$/, "", line)
  if (line != "") emit("cmd", line, comment)
}
function scan_prose(text,    rest, inline) {
  rest = text
  while (match(rest, /Set `[a-z_]+\.[a-z_]+: [^`]+`/)) {
    inline = substr(rest, RSTART + 5, RLENGTH - 6)
    emit("set", inline, "")
    rest = substr(rest, RSTART + RLENGTH)
  }
  rest = text
  while (match(rest, /`(tumble-view --listen|lcm-logger )[^`]*`/)) {
    emit("watch", substr(rest, RSTART + 1, RLENGTH - 2), "")
    rest = substr(rest, RSTART + RLENGTH)
  }
}
BEGIN { inside = 0; number = 0; fence = ""; pending = ""; paragraph = "" }
!inside && !done && $0 ~ from { inside = 1; first_line = NR }
inside && NR != first_line && fence == "" && $0 ~ to { inside = 0; done = 1 }
!inside { next }
fence == "" && /^```sh[ \t]*$/ { scan_prose(paragraph); paragraph = ""; fence = "sh"; next }
fence == "" && /^```yaml[ \t]*$/ { scan_prose(paragraph); paragraph = ""; fence = "yaml"; next }
fence != "" && /^```/ { fence = ""; next }
fence == "sh" {
  line = $0
  if (line ~ /\\$/) { sub(/[ \t]*\\$/, " ", line); pending = pending line; next }
  if (pending != "") { sub(/^[ \t]+/, "", line); line = pending line; pending = "" }
  emit_command(line)
  next
}
fence == "yaml" { emit("paste", $0, ""); next }
$0 ~ step {
  scan_prose(paragraph); paragraph = ""
  match($0, /[0-9]+/)
  number = substr($0, RSTART, RLENGTH) + 0
}
/^[ \t]*$/ { scan_prose(paragraph); paragraph = ""; next }
{ paragraph = paragraph " " $0 }
END { scan_prose(paragraph) }
