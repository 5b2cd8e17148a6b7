# Arranged parts keep the spacing from the plate's edges (issue 32 item 19: they sat flush on
# the far edge and at x = 0); given positions may still touch the edge.
cd "$TMP"
"$HOVOX" generate box max=6,6,0.5 -o pin.stl >/dev/null
"$HOVOX" tray -o t --part pin.stl:VeroPureWhitex2 --arrange yes --dry-run >plan; echo "rc=$?"; grep "^part " plan
"$HOVOX" tray -o t --part pin.stl:VeroPureWhitex2 --arrange yes --spacing 8 --dry-run >plan; echo "rc=$?"; grep "^part " plan
"$HOVOX" tray -o t --part pin.stl:VeroPureWhitex2 --arrange yes --spacing 0 --dry-run >plan; echo "rc=$?"; grep "^part " plan
"$HOVOX" tray -o t --part pin.stl:VeroPureWhite@3,387 --dry-run >plan; echo "rc=$?"; grep "^part " plan
