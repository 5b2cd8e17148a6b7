$HOVOX probe tests/data/models/gap3.vdb 1,2
