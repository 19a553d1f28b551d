#!/usr/bin/env bash
# Re-make every image the README shows, with the commands the README names under each.
# Run from the repository root with brushwork installed (after install.sh: .venv/bin/brushwork).
set -euo pipefail
cd "$(dirname "$0")/.."
bw="${BRUSHWORK:-.venv/bin/brushwork}"
py="${PYTHON:-.venv/bin/python}"
# a fresh work folder: batch and font resume from what a folder already holds
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$bw" render 永和九年 -o docs/yonghe.png
# 永 at 2048 px in the two styles, side by side
"$bw" render 永 --size 2048 --style kai -o "$work/yong_kai.png"
"$bw" render 永 --size 2048 --style xing -o "$work/yong_xing.png"
"$py" -c 'import sys, cv2, numpy as np; cv2.imwrite(sys.argv[3], np.hstack([cv2.imread(p) for p in sys.argv[1:3]]))' \
  "$work/yong_kai.png" "$work/yong_xing.png" docs/yong_2048.png
"$bw" gallery -o docs/gallery.png --views docs/brush_view.png
"$bw" batch --chars "$(cat docs/sheet_chars.txt)" --size 1024 --sheet-px 320 --out "$work/sheet" \
  --sheet docs/sheet.png --no-progress
# 3-D outlines: the meshes of $BRUSHWORK_MESHES (default the shared test meshes) in two styles
"$py" -m brushwork.outline3d.sheet --meshes "${BRUSHWORK_MESHES:-../shared/data/meshes}" \
  --styles baimiao,xieyi --size 400 -o docs/outlines.png
# ... and meshes of bench outline's generated set: low-poly ones and a smooth bunny
mkdir -p "$work/lowpoly"
"$py" -c 'import sys; from brushwork.bench.outline import bunny_blob, lowpoly_set; m = lowpoly_set()
m["bunny_blob"] = bunny_blob()
for name in sys.argv[2:]: m[name].export(f"{sys.argv[1]}/{name}.ply")' "$work/lowpoly" box bunny_blob faceted_head torus_lowpoly
"$py" -m brushwork.outline3d.sheet --meshes "$work/lowpoly" --styles baimiao,xieyi --size 400 -o docs/outlines_lowpoly.png
# a line set in a brushwork font by headless Chromium (needs chromium and chromium-driver)
fonts="$work/font"
mkdir -p "$fonts"
"$bw" font --chars 永和九年岁在癸丑暮春 -o "$fonts/line.woff2" --no-progress
"$py" -m brushwork.font.browser "$fonts/line.woff2" 永和九年岁在癸丑暮春 docs/font_line.png --px 96
# the brush at three presses above the variable font's instances there
"$bw" font --chars 永和九年 -o "$fonts/weights.otf" --variable --no-progress
"$py" -m brushwork.font.weights "$fonts/weights.otf" 永和九年 docs/font_weights.png --px 96
# the page of `brushwork paint`, as its test in headless Chromium paints it (needs the paint extra and chromium)
BRUSHWORK_SCREENSHOT=docs/paint.png "$py" -m pytest -q tests/test_paint.py -k paints_with_a_pen
