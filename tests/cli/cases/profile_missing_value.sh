$HOVOX profile tests/data/models/gap3.vdb --from 0,0,0 --to
