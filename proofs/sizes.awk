# proofs/sizes.awk: the lines of specification and of proof of a .v file,
# printed as "FILE SPEC PROOF". Proof lines: from "Proof." to "Qed." (both
# included, also one-line proofs). Specification lines: the other lines
# that are neither blank nor comments (a comment starts a line with "(*").
BEGIN { spec = 0; proof = 0; inproof = 0; incomment = 0 }
{
  line = $0; sub(/^[ \t]+/, "", line)
  if (incomment) { if (index($0, "*)")) incomment = 0; next }
  if (line == "") next
  if (substr(line, 1, 2) == "(*") { if (!index($0, "*)")) incomment = 1; next }
  if (inproof || line ~ /^Proof\./) {
    proof++; inproof = 1
    if ($0 ~ /(Qed|Defined|Admitted)\.[ \t]*$/) inproof = 0
    next
  }
  spec++
}
END { printf "%s %d %d\n", FILENAME, spec, proof }
