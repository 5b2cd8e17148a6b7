# without --mesh, layers cuts the shape the model records (issue 28): a missing model is an I/O error
$HOVOX layers model.vdb -o "$TMP/stack"
