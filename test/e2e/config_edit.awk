# The two edits of tumbled.yaml the set-up documents tell the reader to make,
# for quickstart_test.sh; prints the edited file.
#   awk -v set='lidar.source_ip: "192.168.1.200"' -f config_edit.awk tumbled.yaml
#     gives that key of that section the value, keeping the line's comment;
#   awk -v section=imu -v paste=FILE -f config_edit.awk tumbled.yaml
#     puts FILE's lines (tumble-calib rig's, two-space indented) at the top of
#     the section in place of the keys of the same names, children and all.
# Exits 3 when the section or the key to set is not in the file: the document
# names a key the configuration does not have.
BEGIN {
  if (set != "") {
    split(set, parts, ": ")
    section = substr(parts[1], 1, index(parts[1], ".") - 1)
    key = substr(parts[1], index(parts[1], ".") + 1)
    value = substr(set, length(parts[1]) + 3)
  }
  if (paste != "") {
    while ((getline line < paste) > 0) {
      pasted[++pasted_lines] = line
      if (line ~ /^  [a-zA-Z_]+:/) {
        name = line
        sub(/^  /, "", name)
        sub(/:.*/, "", name)
        replaced[name] = 1
      }
    }
  }
  in_section = 0; found_section = 0; found_key = 0; dropping = 0
}
/^[a-zA-Z_]+:/ {
  in_section = ($0 ~ "^" section ":")
  dropping = 0
  print
  if (in_section) {
    found_section = 1
    for (i = 1; i <= pasted_lines; i++) print pasted[i]
  }
  next
}
in_section && dropping && /^(   |[ \t]*$)/ { next }
in_section { dropping = 0 }
in_section && /^  [a-zA-Z_]+:/ {
  name = $0
  sub(/^  /, "", name)
  sub(/:.*/, "", name)
  if (name in replaced) { dropping = 1; next }
  if (set != "" && name == key) {
    comment = ""
    if (match($0, /[ \t]+# .*/)) comment = substr($0, RSTART)
    print "  " key ": " value comment
    found_key = 1
    next
  }
}
{ print }
END {
  if (!found_section || (set != "" && !found_key)) exit 3
}
