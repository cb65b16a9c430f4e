#!/usr/bin/env bash
# Refreshes the README's images of the viewer: runs the browser tests that take them (headless
# Chromium; CI=1 so that a missing browser is an error, not a skip) and copies their
# screenshots from target/screenshots/ to docs/images/.
#
# Usage: scripts/viewer-images.sh
#   view-simulate.png  the default day at 10:30, a flight clicked   (tests/viewer/page.rs)
#   view-narrow.png    the same day on a 600 px wide touch screen    (tests/viewer/truth.rs)
#   view-live.png      muse serve's live page, a zone announced live (tests/viewer/live.rs)
#   view-layers.png    a four-layer day, a flight's altitude over time (tests/viewer/layers.rs)
set -euo pipefail
cd "$(dirname "$0")/.."
CI=1 cargo test --test viewer
for image in view-simulate.png view-narrow.png view-live.png view-layers.png; do
  cp "target/screenshots/$image" "docs/images/$image"
  echo "docs/images/$image"
done
