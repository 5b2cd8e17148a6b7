# review item 6: export of a Boolean's shape (level sets, CSG, volumeToMesh in the OpenVDB
# bridge) honours --threads: TBB is held to hv_threads() (before, it took every processor of the
# affinity mask whatever --threads said), and the surface is the same bytes on 1 and 2 threads.
# The threads TBB starts are counted with strace: those cloned after TBB loads its allocator
# (libtbbmalloc; the threads before it are log4cplus's, started as the bridge loads).
here=$(pwd)
cd "$TMP" || exit 1
/usr/bin/python3 "$here/tests/cli/cases/holed_plate.py" 20,10,5 2.5 64 0.5 subtract holed.vdb || exit 1
$HOVOX export holed.vdb -o t1.stl --threads 1 -q; echo "rc=$?"
$HOVOX export holed.vdb -o t2.stl --threads 2 -q 2>/dev/null; echo "rc=$?"
cmp t1.stl t2.stl && echo "1 and 2 threads: the same bytes"
# (LeakSanitizer cannot run under strace: off for this run in the sanitized build)
ASAN_OPTIONS=detect_leaks=0 strace -f -qq -e trace=clone,clone3,openat -e signal=none -o st.txt \
    "$HOVOX" export holed.vdb -o s1.stl --threads 1 -q; echo "rc=$?"
grep -q libtbbmalloc st.txt && echo "TBB ran: yes"
echo "threads TBB started at --threads 1: $(sed -n '/libtbbmalloc/,$p' st.txt | grep -c CLONE_THREAD)"
cmp t1.stl s1.stl && echo "the same bytes again"
