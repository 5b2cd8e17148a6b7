$HOVOX probe tests/data/models/gap3.vdb
