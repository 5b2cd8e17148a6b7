$HOVOX probe tests/data/models/ungraded.vdb 1,2,3
