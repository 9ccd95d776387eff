# Sourced by scripts/mocap_ranking.sh and scripts/mocap_windows.sh.
# evaluate_fitting MOREAU RECORDING OUT "LIST LIST …" [evaluate-gaps options …]: evaluate-gaps on
# RECORDING into OUT with the first list of gap lengths that fits (exit 2 from a longer list: its
# longest gap does not fit in the recording's complete part, try the next, shorter one); any
# other failure prints the tool's messages and exits the script.
evaluate_fitting() {
  local moreau=$1 recording=$2 out=$3 lists=$4 gaps status
  shift 4
  for gaps in $lists; do
    status=0
    "$moreau" evaluate-gaps "$recording" --gap-seconds "$gaps" --out "$out" "$@" > /dev/null \
      2> "$out.log" || status=$?
    [ "$status" = 2 ] && [ "$gaps" != "${lists##* }" ] && continue
    [ "$status" = 0 ] || { cat "$out.log" >&2; exit 1; }
    return 0
  done
}
