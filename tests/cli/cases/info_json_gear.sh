$HOVOX info --json "$SHARED/meshes/helical_gear.stl"
