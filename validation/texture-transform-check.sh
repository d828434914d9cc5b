#!/usr/bin/env bash
# KHR_texture_transform against Mitsuba (docs/gltf.md, "glTF 2.0"), in CI: copies the shared
# DamagedHelmet with a transform added to each of its four textures (the JSON chunk of the GLB
# edited, the binary chunk kept), and validates scenes/validation/shared/damaged-helmet.toml's
# view of it; fails when `validate` says the scene fails. The normal texture at twice its
# frequency is more sensitive to the two renderers' rounding of texture coordinates: agreement
# counts the one-ulp rounding band (`validation::rounding`; 99.854% of the pixels within 1e-3 at
# pixel centres without it, 99.922% with it, on 2026-11-24). Ignoring the transforms in the
# plugin gives about 71%.
#   Usage: validation/texture-transform-check.sh [OUT_DIR]   (needs ../shared and Mitsuba)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-target/texture-transform-check}
helmet=../shared/data/gltf/DamagedHelmet/glTF-Binary/DamagedHelmet.glb
[ -f "$helmet" ] || { echo "SKIPPED: $helmet is missing" >&2; exit 1; }
validation/install.sh >/dev/null
cargo build --release --quiet
mkdir -p "$out"
validation/.venv/bin/python - "$helmet" "$out/helmet-transformed.glb" <<'PY'
import json, struct, sys
src, dst = sys.argv[1], sys.argv[2]
data = open(src, "rb").read()
json_len = struct.unpack("<I", data[12:16])[0]
doc = json.loads(data[20:20 + json_len])
rest = data[20 + json_len:]
m = doc["materials"][0]
def transform(offset, rotation, scale):
    return {"KHR_texture_transform": {"offset": offset, "rotation": rotation, "scale": scale}}
m["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = transform([0.1, 0.2], 0.3, [1.5, 0.8])
m["pbrMetallicRoughness"]["metallicRoughnessTexture"]["extensions"] = transform([0.0, 0.1], -0.2, [1.2, 1.2])
m["normalTexture"]["extensions"] = transform([0.05, 0.0], 0.5, [2.0, 2.0])
m["emissiveTexture"]["extensions"] = transform([0.1, 0.0], 0.0, [1.0, 1.0])
doc.setdefault("extensionsUsed", []).append("KHR_texture_transform")
chunk = json.dumps(doc).encode()
chunk += b" " * (-len(chunk) % 4)
header = b"glTF" + struct.pack("<II", 2, 12 + 8 + len(chunk) + len(rest))
open(dst, "wb").write(header + struct.pack("<I", len(chunk)) + b"JSON" + chunk + rest)
PY
sed -e "s#^mesh = .*#mesh = \"$(cd "$out" && pwd)/helmet-transformed.glb\"#" \
  scenes/validation/shared/damaged-helmet.toml > "$out/helmet-transformed.toml"
status=0
./target/release/pointshade validate --report "$out/report" "$out/helmet-transformed.toml" >/dev/null 2>&1 || status=$?
grep '^| scene\|^| helmet' "$out/report/summary.md" || true
if [ "$status" != 0 ]; then
  echo "FAILED: the transformed DamagedHelmet does not agree with Mitsuba (report: $out/report/index.html)" >&2
  exit 1
fi
echo "ok: KHR_texture_transform agrees with Mitsuba"
