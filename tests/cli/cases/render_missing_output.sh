$HOVOX render model.vdb
