#!/usr/bin/env bash
# Re-make every image the README shows, with the commands the README names under each.
# Run from the repository root with brushwork installed (after install.sh: .venv/bin/brushwork).
set -euo pipefail
cd "$(dirname "$0")/.."
bw="${BRUSHWORK:-.venv/bin/brushwork}"
"$bw" render 永和九年 -o docs/yonghe.png
"$bw" gallery -o docs/gallery.png --views docs/brush_view.png
"$bw" batch --chars "$(cat docs/sheet_chars.txt)" --size 256 --out "${TMPDIR:-/tmp}/brushwork-sheet" \
  --sheet docs/sheet.png --no-progress
# the page of `brushwork paint`, as its test in headless Chromium paints it (needs the paint extra and chromium)
BRUSHWORK_SCREENSHOT=docs/paint.png "${PYTHON:-$(dirname "$bw")/python}" -m pytest -q tests/test_paint.py -k paints_with_a_pen
