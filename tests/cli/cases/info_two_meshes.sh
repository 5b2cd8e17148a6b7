$HOVOX info "$SHARED/meshes/bolt_colored_header.stl" "$SHARED/meshes/bunny_1500.stl"
