#!/usr/bin/env bash
# Camera change -> frame latency of `smoothlab view`, measured over HTTP as the page sees it.
#
#   scenes/tools/view_latency.sh [MESH] [SCHEME] [WxH] [CHANGES]
#
# Starts `smoothlab view MESH --scheme SCHEME` (release binary), then CHANGES times: posts a new
# camera (an orbit step around the framed view) once the previous one has converged, and reads
# the frames of that camera. Prints, per change, the server's time from the request to the
# coarse frame (1/4 size, 1 spp), to the full-size frame at 1 spp, and to the converged frame
# (the scene's spp), each with that pass's own render time in parentheses. Then CHANGES times
# the interactive case: a camera posted while the converged pass of the previous one renders,
# which must first stop at its next tile: request to coarse frame. The surface and BVH are
# built before the URL is printed, so no change includes them.
set -euo pipefail
cd "$(dirname "$0")/../.."
mesh=${1:-scenes/bunny.obj}
scheme=${2:-hb}
size=${3:-1024x768}
changes=${4:-5}
w=${size%x*}
h=${size#*x}
bin=target/release/smoothlab
log=$(mktemp)
"$bin" view "$mesh" --scheme "$scheme" --no-browser --port 0 --out "$(mktemp -d)" >"$log" 2>&1 &
pid=$!
trap 'kill $pid 2>/dev/null || true; rm -f "$log"' EXIT
until grep -q '^open ' "$log"; do sleep 0.1; done
head -1 "$log"
url=$(sed -n 's/^open //p' "$log")
host=${url#http://}
host=${host%%/*}
token=${url#*token=}
info=$(curl -s "http://$host/info?token=$token&w=$w&h=$h")
# The framed eye and target, orbited about the vertical through the target by `step` radians.
camera() {
    python3 - "$info" "$1" <<'EOF'
import json, math, sys
info, step = json.loads(sys.argv[1]), float(sys.argv[2])
e, t = info["camera"]["eye"], info["camera"]["target"]
dx, dz = e[0] - t[0], e[2] - t[2]
c, s = math.cos(step), math.sin(step)
eye = [t[0] + c * dx + s * dz, e[1], t[2] - s * dx + c * dz]
print(json.dumps({"eye": eye, "target": t, "up": [0, 1, 0]}))
EOF
}
seq=0
printf '%-7s %-22s %-22s %-22s\n' change "coarse ms (render)" "full 1 spp (render)" "converged (render)"
for k in $(seq 1 "$changes"); do
    body="{\"camera\": $(camera "0.$k"), \"render\": {\"size\": [$w, $h]}}"
    gen=$(curl -s -X POST "http://$host/view?token=$token" -d "$body" | python3 -c 'import json,sys; print(json.load(sys.stdin)["generation"])')
    row=()
    while [ ${#row[@]} -lt 3 ]; do
        headers=$(curl -s -D - -o /dev/null "http://$host/frame?token=$token&after=$seq")
        get() { printf '%s' "$headers" | tr -d '\r' | sed -n "s/^$1: //Ip"; }
        [ -n "$(get X-Seq)" ] || continue
        seq=$(get X-Seq)
        [ "$(get X-Generation)" = "$gen" ] || continue
        row+=("$(get X-Since-Request-Ms) ($(get X-Render-Ms))")
    done
    printf '%-7s %-22s %-22s %-22s\n' "$k" "${row[0]}" "${row[1]}" "${row[2]}"
done
echo "camera change while the converged pass renders -> coarse frame, ms (render)"
for k in $(seq 1 "$changes"); do
    for step in a b; do
        body="{\"camera\": $(camera "-0.$k$([ $step = b ] && echo 5)"), \"render\": {\"size\": [$w, $h]}}"
        gen=$(curl -s -X POST "http://$host/view?token=$token" -d "$body" | python3 -c 'import json,sys; print(json.load(sys.stdin)["generation"])')
        # a: wait for the full-size 1 spp frame, so the converged pass is rendering; b: its coarse frame.
        want=$([ $step = a ] && echo 1 || echo 0)
        while :; do
            headers=$(curl -s -D - -o /dev/null "http://$host/frame?token=$token&after=$seq")
            get() { printf '%s' "$headers" | tr -d '\r' | sed -n "s/^$1: //Ip"; }
            [ -n "$(get X-Seq)" ] || continue
            seq=$(get X-Seq)
            [ "$(get X-Generation)" = "$gen" ] && [ "$(get X-Level)" = "$want" ] && break
        done
    done
    echo "$k $(get X-Since-Request-Ms) ($(get X-Render-Ms))"
done
