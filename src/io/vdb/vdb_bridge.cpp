// volumes/vdb_bridge.cpp - the only code that includes OpenVDB: it writes hovox's volumes (kept
// in C by volume.c) as .vdb files, one grid at a time, and reads the .vdb files the native reader
// (vdb_read.c) leaves to it, handing their leaves over to volume.c. Built as
// plugins/hovox-vdb.so and loaded only for those (linking libopenvdb costs ~40 ms of start-up). Every entry catches all exceptions
// (HV_CATCH) and turns them into a status plus what(); nothing propagates into C.
#include "vdb_bridge.h"

#include "core/bridge.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <openvdb/io/Compression.h>
#include <openvdb/math/Vec3.h>

#include <type_traits>

// OpenVDB 10.0's bloscFromStream/unzipFromStream read a chunk stored uncompressed (a length
// n <= 0 before it) as -n bytes into a buffer of the size the tree expects, without comparing
// the two: a damaged length writes past the buffer (found by fuzz_vdb under ASan: a heap
// overflow, then glibc aborts). hovox's copy of readData checks the length first, for the
// value types whose reading this plugin compiles; the rest is OpenVDB's readData unchanged.
namespace openvdb {
OPENVDB_USE_VERSION_NAMESPACE
namespace OPENVDB_VERSION_NAME {
namespace io {
namespace hovox_checked {
template<typename T>
inline void readData(std::istream &is, T *data, Index count, uint32_t compression, DelayedLoadMetadata *metadata,
                     size_t metadataOffset)
{
    const bool seek = data == nullptr;
    const bool compressed = compression & (COMPRESS_BLOSC | COMPRESS_ZIP);
    if (metadata && seek && compressed) {
        is.seekg(std::streamoff(metadata->getCompressedSize(metadataOffset)), std::ios_base::cur);
        return;
    }
    if (compressed && !seek) {
        const std::streampos at = is.tellg();
        Int64 n = 0;
        is.read(reinterpret_cast<char *>(&n), sizeof n);
        is.seekg(at);
        if (n <= 0 && uint64_t(0) - uint64_t(n) != uint64_t(sizeof(T)) * count)
            OPENVDB_THROW(IoError, "a stored chunk of " + std::to_string(uint64_t(0) - uint64_t(n)) +
                                       " bytes where " + std::to_string(uint64_t(sizeof(T)) * count) +
                                       " belong: the file is damaged");
    }
    if (compression & COMPRESS_BLOSC) bloscFromStream(is, reinterpret_cast<char *>(data), sizeof(T) * count);
    else if (compression & COMPRESS_ZIP) unzipFromStream(is, reinterpret_cast<char *>(data), sizeof(T) * count);
    else if (seek) is.seekg(std::streamoff(sizeof(T) * count), std::ios_base::cur);
    else is.read(reinterpret_cast<char *>(data), std::streamsize(sizeof(T) * count));
}
} // namespace hovox_checked
#define HV_CHECKED_READ(T)                                                                                    \
    template<>                                                                                                \
    inline void readData<T>(std::istream & is, T * data, Index count, uint32_t compression,                    \
                            DelayedLoadMetadata * metadata, size_t metadataOffset)                             \
    {                                                                                                         \
        hovox_checked::readData(is, data, count, compression, metadata, metadataOffset);                      \
    }
HV_CHECKED_READ(bool)
HV_CHECKED_READ(float)
HV_CHECKED_READ(double)
HV_CHECKED_READ(int32_t)
HV_CHECKED_READ(int64_t)
HV_CHECKED_READ(math::half)
HV_CHECKED_READ(math::Vec3<float>)
HV_CHECKED_READ(math::Vec3<double>)
HV_CHECKED_READ(math::Vec3<int32_t>)
#undef HV_CHECKED_READ
} // namespace io
} // namespace OPENVDB_VERSION_NAME
} // namespace openvdb

// OpenVDB 10.0's RootNode::readTopology allocates each child with a plain new and reads its
// topology before the root owns it: when the read throws (a damaged or truncated file) the
// child's whole subtree leaks, 270 KB per failed load of a small model (found by fuzz_vdb:
// the fuzzer grew to its 4 GiB limit in three minutes). Freeing it is not enough: an internal
// node whose read stopped part way has child-mask bits on for slots that still hold values, and
// its destructor would delete those values as pointers (found by fuzz_vdb once the leak was
// fixed). hovox's copies, for the trees this plugin compiles: the root hands the child to a
// unique_ptr until its table holds it; an internal node whose read throws turns off the child
// bits of the slots it had not filled (they become background tiles) before passing the error
// on, so the partial subtree is a valid tree to destroy. Files in the format before OpenVDB 1.0
// (file version < 213) are refused instead of read: their root table size is 2^(sum of three
// log2 extents) taken from the file, with no bound.
#include <openvdb/tree/InternalNode.h>
#include <openvdb/tree/LeafNode.h>
#include <openvdb/tree/LeafNodeBool.h>
#include <openvdb/tree/RootNode.h>
#include <memory>
namespace openvdb {
OPENVDB_USE_VERSION_NAMESPACE
namespace OPENVDB_VERSION_NAME {
namespace tree {
#define HV_CHECKED_INTERNAL(NODE)                                                                             \
    template<>                                                                                                \
    inline void NODE::readTopology(std::istream & is, bool fromHalf)                                          \
    {                                                                                                         \
        const ValueType background = !io::getGridBackgroundValuePtr(is)                                       \
                                         ? zeroVal<ValueType>()                                               \
                                         : *static_cast<const ValueType *>(io::getGridBackgroundValuePtr(is)); \
        NodeMaskType filled; /* child slots that hold a child */                                             \
        try {                                                                                                 \
            mChildMask.load(is); /* inside: a mask read part way is repaired too */                          \
            mValueMask.load(is);                                                                              \
            if (io::getFormatVersion(is) < OPENVDB_FILE_VERSION_INTERNALNODE_COMPRESSION) {                   \
                for (Index i = 0; i < NUM_VALUES; ++i) {                                                      \
                    if (this->isChildMaskOn(i)) {                                                             \
                        ChildNodeType *child =                                                                \
                            new ChildNodeType(PartialCreate(), offsetToGlobalCoord(i), background);           \
                        mNodes[i].setChild(child);                                                            \
                        filled.setOn(i);                                                                      \
                        child->readTopology(is);                                                              \
                    } else {                                                                                  \
                        ValueType value;                                                                      \
                        is.read(reinterpret_cast<char *>(&value), sizeof(ValueType));                         \
                        mNodes[i].setValue(value);                                                            \
                    }                                                                                         \
                }                                                                                             \
                return;                                                                                       \
            }                                                                                                 \
            const bool oldVersion = io::getFormatVersion(is) < OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION;    \
            const Index numValues = oldVersion ? mChildMask.countOff() : NUM_VALUES;                          \
            {                                                                                                 \
                std::unique_ptr<ValueType[]> values(new ValueType[numValues]);                                \
                io::readCompressedValues(is, values.get(), numValues, mValueMask, fromHalf);                  \
                Index n = 0;                                                                                  \
                for (ValueAllIter it = this->beginValueAll(); it; ++it)                                       \
                    mNodes[it.pos()].setValue(values[oldVersion ? n++ : it.pos()]);                           \
            }                                                                                                 \
            for (ChildOnIter it = this->beginChildOn(); it; ++it) {                                           \
                ChildNodeType *child = new ChildNodeType(PartialCreate(), it.getCoord(), background);         \
                mNodes[it.pos()].setChild(child);                                                             \
                filled.setOn(it.pos());                                                                       \
                child->readTopology(is, fromHalf);                                                            \
            }                                                                                                 \
        } catch (...) {                                                                                       \
            for (Index i = 0; i < NUM_VALUES; ++i)                                                            \
                if (mChildMask.isOn(i) && !filled.isOn(i)) {                                                  \
                    mChildMask.setOff(i);                                                                     \
                    mNodes[i].setValue(background);                                                           \
                }                                                                                             \
            throw;                                                                                            \
        }                                                                                                     \
    }
#define HV_NODE4(T) InternalNode<LeafNode<T, 3>, 4>
#define HV_NODE5(T) InternalNode<InternalNode<LeafNode<T, 3>, 4>, 5>
#define HV_CHECKED_ROOT(T)                                                                                    \
    HV_CHECKED_INTERNAL(HV_NODE4(T))                                                                          \
    HV_CHECKED_INTERNAL(HV_NODE5(T))                                                                          \
    template<>                                                                                                \
    inline bool RootNode<InternalNode<InternalNode<LeafNode<T, 3>, 4>, 5>>::readTopology(std::istream & is,    \
                                                                                         bool fromHalf)       \
    {                                                                                                         \
        this->clear();                                                                                        \
        const uint32_t version = io::getFormatVersion(is);                                                    \
        if (version < OPENVDB_FILE_VERSION_ROOTNODE_MAP)                                                      \
            OPENVDB_THROW(IoError, "file format version " + std::to_string(version) +                        \
                                       " predates OpenVDB 1.0 (213) and is not read");                        \
        is.read(reinterpret_cast<char *>(&mBackground), sizeof(ValueType));                                  \
        io::setGridBackgroundValuePtr(is, &mBackground);                                                      \
        Index numTiles = 0, numChildren = 0;                                                                  \
        is.read(reinterpret_cast<char *>(&numTiles), sizeof(Index));                                          \
        is.read(reinterpret_cast<char *>(&numChildren), sizeof(Index));                                       \
        if (numTiles == 0 && numChildren == 0) return false;                                                  \
        Int32 vec[3];                                                                                         \
        ValueType value;                                                                                      \
        bool active;                                                                                          \
        for (Index n = 0; n < numTiles; ++n) {                                                                \
            is.read(reinterpret_cast<char *>(vec), 3 * sizeof(Int32));                                        \
            is.read(reinterpret_cast<char *>(&value), sizeof(ValueType));                                     \
            is.read(reinterpret_cast<char *>(&active), sizeof(bool));                                         \
            mTable[Coord(vec)] = NodeStruct(Tile(value, active));                                             \
        }                                                                                                     \
        for (Index n = 0; n < numChildren; ++n) {                                                             \
            is.read(reinterpret_cast<char *>(vec), 3 * sizeof(Int32));                                        \
            std::unique_ptr<ChildNodeType> child(new ChildNodeType(PartialCreate(), Coord(vec), mBackground)); \
            child->readTopology(is, fromHalf);                                                                \
            NodeStruct &slot = mTable[Coord(vec)];                                                            \
            if (slot.child) delete slot.child; /* a repeated origin: OpenVDB leaks the first */               \
            slot = NodeStruct(*child.release());                                                              \
        }                                                                                                     \
        return true;                                                                                          \
    }
typedef math::Vec3<float> hv_vec3f;
typedef math::Vec3<double> hv_vec3d;
typedef math::Vec3<int32_t> hv_vec3i;
HV_CHECKED_ROOT(bool)
HV_CHECKED_ROOT(float)
HV_CHECKED_ROOT(double)
HV_CHECKED_ROOT(int32_t)
HV_CHECKED_ROOT(int64_t)
HV_CHECKED_ROOT(hv_vec3f)
HV_CHECKED_ROOT(hv_vec3d)
HV_CHECKED_ROOT(hv_vec3i)
#undef HV_CHECKED_ROOT
#undef HV_CHECKED_INTERNAL
#undef HV_NODE4
#undef HV_NODE5
} // namespace tree
} // namespace OPENVDB_VERSION_NAME
} // namespace openvdb

#include <openvdb/openvdb.h>
#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/math/Maps.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <atomic>
#include <deque>
#include <exception>
#include <map>
#include <thread>
#include <mutex>
#include <new>
#include <string>
#include <vector>

namespace {

using namespace hv_bridge;
enum { T_FLOAT = 1, T_BOOL = 2 };

// A library's message on one line: printable characters only, runs of blanks folded, at most
// 200 characters (OpenVDB may echo file bytes or pad with kilobytes of spaces).
std::string one_line(const std::string &in)
{
    std::string out;
    for (char c : in) {
        unsigned char u = static_cast<unsigned char>(c);
        char w = u >= 32 && u < 127 ? c : ' ';
        if (w == ' ' && (out.empty() || out.back() == ' ')) continue;
        out.push_back(w);
        if (out.size() >= 200) {
            out += "...";
            break;
        }
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
    return out;
}

struct Cancelled {};
struct Damaged { // found by hovox's own checks, said as is
    std::string what;
};

// OpenVDB's warnings go to std::cerr from its headers ("WARNING: multi-buffer trees are no
// longer supported" for a damaged file) and, through log4cplus's console appender, to std::cout
// from the library ("WARN: unsupported VDB file format"): on stdout they would corrupt what a
// command prints there. While OpenVDB reads, both are caught here, so hovox's one-line message
// stays the only one.
// The streams are process-wide: loads on several threads take turns here, so each restores
// exactly what it replaced.
std::mutex g_quiet_mutex;

class QuietStreams {
public:
    QuietStreams()
        : mLock(g_quiet_mutex), mErr(std::cerr.rdbuf(&mSink)), mOut(std::cout.rdbuf(&mSink))
    {
    }
    ~QuietStreams()
    {
        std::cerr.rdbuf(mErr);
        std::cout.rdbuf(mOut);
    }

private:
    // discards everything and holds no state: grids read on several threads may all write to it
    class Sink : public std::streambuf {
    protected:
        int_type overflow(int_type c) override { return traits_type::not_eof(c); }
        std::streamsize xsputn(const char *, std::streamsize n) override { return n; }
    };
    std::lock_guard<std::mutex> mLock;
    Sink mSink;
    std::streambuf *mErr, *mOut;
};

// The file version in the header (after the 8-byte magic): a version newer than this OpenVDB's
// is refused (a damaged header, or a file this build cannot read) rather than parsed on with a
// warning. 0 when the header cannot be read (OpenVDB then says why).
uint32_t file_version(const char *path)
{
    unsigned char h[12];
    FILE *f = std::fopen(path, "rb");
    size_t got = f ? std::fread(h, 1, sizeof h, f) : 0;
    if (f) std::fclose(f);
    if (got != sizeof h) return 0;
    return uint32_t(h[8]) | uint32_t(h[9]) << 8 | uint32_t(h[10]) << 16 | uint32_t(h[11]) << 24;
}

// While OpenVDB parses a file, the address space may grow by at most `allowance` bytes: a
// damaged length field (a metadata string of 2^31 bytes) then fails as bad_alloc instead of
// taking gigabytes before the read notices the damage. Lifted again before any expansion.
// Not under AddressSanitizer, which reserves terabytes of shadow memory.
class AddressLimit {
public:
    explicit AddressLimit(uint64_t allowance)
    {
#if !defined(__SANITIZE_ADDRESS__)
        long pages = 0, page = sysconf(_SC_PAGESIZE);
        FILE *f = std::fopen("/proc/self/statm", "r");
        if (!f) return;
        int got = std::fscanf(f, "%ld", &pages);
        std::fclose(f);
        if (got != 1 || page <= 0 || getrlimit(RLIMIT_AS, &mOld) != 0) return;
        rlimit lim = mOld;
        rlim_t want = rlim_t(pages) * rlim_t(page) + rlim_t(allowance);
        if (mOld.rlim_cur != RLIM_INFINITY && mOld.rlim_cur < want) return;
        lim.rlim_cur = want;
        mSet = setrlimit(RLIMIT_AS, &lim) == 0;
#else
        (void)allowance;
#endif
    }
    ~AddressLimit() { lift(); }
    void lift()
    {
        if (mSet) setrlimit(RLIMIT_AS, &mOld);
        mSet = false;
    }

private:
    rlimit mOld{};
    bool mSet = false;
};

// A file buffer that polls `cancel` every 4 MiB read or written; C++ streams then see an
// exception, which the entries below turn into status 6.
class CheckedBuf : public std::filebuf {
public:
    explicit CheckedBuf(hv_vdb_cancel_fn cancel) : mCancel(cancel) {}

protected:
    std::streamsize xsputn(const char *s, std::streamsize n) override
    {
        poll(n);
        return std::filebuf::xsputn(s, n);
    }
    std::streamsize xsgetn(char *s, std::streamsize n) override
    {
        poll(n);
        return std::filebuf::xsgetn(s, n);
    }

private:
    void poll(std::streamsize n)
    {
        mCount += n;
        if (mCount >= (std::streamsize(4) << 20)) {
            mCount = 0;
            if (mCancel && mCancel()) throw Cancelled();
        }
    }
    hv_vdb_cancel_fn mCancel;
    std::streamsize mCount = 0;
};

// The file buffer loads read through: pread into a 256 KiB window, so the many small reads and
// the position queries and seeks of OpenVDB's reader (a tellg per leaf buffer in readData
// above) cost a copy, not a system call each (std::filebuf asks the kernel for every tellg:
// 9% of loading a model). Polls `cancel` every 4 MiB. A read error or the end of the file is
// the end of input: the checked stream above it throws.
class ReadBuf : public std::streambuf {
public:
    explicit ReadBuf(hv_vdb_cancel_fn cancel) : mCancel(cancel), mBuf(size_t(256) << 10) {}
    // another reader of an open file (pread leaves the descriptor's position alone)
    ReadBuf(hv_vdb_cancel_fn cancel, int fd) : mCancel(cancel), mBuf(size_t(256) << 10), mFd(fd), mOwn(false) {}
    ~ReadBuf() override
    {
        if (mFd >= 0 && mOwn) ::close(mFd);
    }
    bool open(const char *path)
    {
        mFd = ::open(path, O_RDONLY | O_CLOEXEC);
        return mFd >= 0;
    }
    int fd() const { return mFd; }

protected:
    int_type underflow() override
    {
        if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
        mBase = pos();
        size_t got = fill(mBuf.data(), mBuf.size(), mBase);
        setg(mBuf.data(), mBuf.data(), mBuf.data() + got);
        return got ? traits_type::to_int_type(*gptr()) : traits_type::eof();
    }
    std::streamsize xsgetn(char *s, std::streamsize n) override
    {
        poll(n);
        std::streamsize done = 0;
        while (done < n) {
            std::streamsize avail = egptr() - gptr();
            if (avail > 0) {
                std::streamsize k = std::min(avail, n - done);
                std::memcpy(s + done, gptr(), size_t(k));
                gbump(int(k));
                done += k;
            } else if (n - done >= std::streamsize(mBuf.size())) { // large: straight to the caller
                int64_t at = pos();
                size_t got = fill(s + done, size_t(n - done), at);
                mBase = at + int64_t(got);
                setg(mBuf.data(), mBuf.data(), mBuf.data());
                done += std::streamsize(got);
                if (got == 0) break;
            } else if (traits_type::eq_int_type(underflow(), traits_type::eof())) {
                break;
            }
        }
        return done;
    }
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override
    {
        int64_t to = -1;
        if (dir == std::ios_base::beg) to = int64_t(off);
        else if (dir == std::ios_base::cur) to = pos() + int64_t(off);
        else if (struct stat st; fstat(mFd, &st) == 0) to = int64_t(st.st_size) + int64_t(off);
        return seek(to);
    }
    pos_type seekpos(pos_type p, std::ios_base::openmode) override { return seek(int64_t(std::streamoff(p))); }

private:
    int64_t pos() const { return mBase + (gptr() - eback()); }
    pos_type seek(int64_t to)
    {
        if (to < 0) return pos_type(off_type(-1));
        if (to >= mBase && to <= mBase + (egptr() - eback())) {
            setg(eback(), eback() + (to - mBase), egptr());
        } else {
            mBase = to;
            setg(mBuf.data(), mBuf.data(), mBuf.data());
        }
        return pos_type(off_type(to));
    }
    size_t fill(char *dst, size_t n, int64_t at)
    {
        size_t got = 0;
        while (got < n) {
            ssize_t r = ::pread(mFd, dst + got, n - got, off_t(at + int64_t(got)));
            if (r < 0 && errno == EINTR) continue;
            if (r <= 0) break;
            got += size_t(r);
        }
        return got;
    }
    void poll(std::streamsize n)
    {
        mCount += n;
        if (mCount >= (std::streamsize(4) << 20)) {
            mCount = 0;
            if (mCancel && mCancel()) throw Cancelled();
        }
    }
    hv_vdb_cancel_fn mCancel;
    std::vector<char> mBuf;
    int mFd = -1;
    bool mOwn = true;
    int64_t mBase = 0; // file offset of eback()
    std::streamsize mCount = 0;
};

#define HV_CATCH(code) HV_CATCH_PREFIXED(code, "", "OpenVDB")

using openvdb::BoolGrid;
using openvdb::Coord;
using openvdb::FloatGrid;
using openvdb::GridBase;
using openvdb::MaskGrid;

// A file loaded by b_load, until volume.c has copied its leaves out.
struct Volume {
    openvdb::math::Transform::Ptr xf;
    MaskGrid::Ptr topo;                 // the shared active topology
    std::vector<GridBase::Ptr> grids;   // FloatGrid or BoolGrid, same topology as topo
};

openvdb::math::Transform::Ptr make_transform(const double v[3], const double o[3])
{
    openvdb::math::Transform::Ptr xf;
    if (v[0] == v[1] && v[1] == v[2]) {
        xf = openvdb::math::Transform::createLinearTransform(v[0]);
        xf->postTranslate(openvdb::Vec3d(o[0], o[1], o[2]));
    } else {
        openvdb::math::MapBase::Ptr map(new openvdb::math::ScaleTranslateMap(
            openvdb::Vec3d(v[0], v[1], v[2]), openvdb::Vec3d(o[0], o[1], o[2])));
        xf.reset(new openvdb::math::Transform(map));
    }
    return xf;
}

// Make grid g's active topology equal to v.topo (values of new voxels: background).
void match_topology(Volume &v, GridBase &g)
{
    if (FloatGrid *f = dynamic_cast<FloatGrid *>(&g))
        f->tree().topologyUnion(v.topo->tree());
    else if (BoolGrid *b = dynamic_cast<BoolGrid *>(&g))
        b->tree().topologyUnion(v.topo->tree());
}

// --- entries --------------------------------------------------------------------------

const char *b_last_error() { return last_error(); }

void b_destroy(void *impl) { delete static_cast<Volume *>(impl); }

void b_grid_free(void *impl, int g)
{
    Volume *v = static_cast<Volume *>(impl);
    if (g >= 0 && size_t(g) < v->grids.size()) v->grids[size_t(g)].reset();
}

size_t b_leaf_count(const void *impl)
{
    return static_cast<const Volume *>(impl)->topo->tree().leafCount();
}

int b_leaf_topology(const void *impl, int32_t *origins, uint64_t *masks)
{
    try {
        // non-const iteration: getWord() hands out a reference only on a mutable mask
        Volume *v = const_cast<Volume *>(static_cast<const Volume *>(impl));
        size_t i = 0;
        for (auto it = v->topo->tree().beginLeaf(); it; ++it, ++i) {
            const Coord &o = it->origin();
            origins[3 * i] = o.x();
            origins[3 * i + 1] = o.y();
            origins[3 * i + 2] = o.z();
            std::memcpy(masks + 8 * i, &it->getValueMask().template getWord<uint64_t>(0), 8 * sizeof(uint64_t));
        }
        return OK;
    }
    HV_CATCH(E_INTERNAL)
}

int b_leaf_buffers(void *impl, int g, void **buffers)
{
    try {
        Volume *v = static_cast<Volume *>(impl);
        GridBase *gp = v->grids.at(size_t(g)).get();
        FloatGrid *f = dynamic_cast<FloatGrid *>(gp);
        BoolGrid *b = dynamic_cast<BoolGrid *>(gp);
        size_t i = 0;
        for (auto it = v->topo->tree().cbeginLeaf(); it; ++it, ++i) {
            auto *fl = f ? f->tree().probeLeaf(it->origin()) : nullptr;
            auto *bl = b ? b->tree().probeLeaf(it->origin()) : nullptr;
            if (!fl && !bl) // only a damaged file gets here: loading unions every grid with the topology
                return fail(E_BAD_INPUT, "grid '" + one_line(gp->getName()) +
                                             "' does not fit the model's voxel topology: the file is damaged");
            buffers[i] = fl ? static_cast<void *>(fl->buffer().data()) : static_cast<void *>(bl->buffer().data());
        }
        return OK;
    }
    HV_CATCH(E_INTERNAL)
}

// OpenVDB's archive with its protected parts put to hovox's use. Saving writes the grid offsets
// (what io::File writes: the header says so and each grid descriptor holds where its grid
// starts and ends), through hovox's checked stream, so a later load can skip the grids it does
// not want. Loading reads what io::Stream reads (header, file metadata, grid descriptors and
// grids, instances connected) from a checked stream, but with offsets in the file it seeks past
// the grids `want` turns down instead of reading them; a file without offsets (io::Stream's
// format, hovox before issue 17) is read whole and the unwanted grids dropped.
class HvArchive : public openvdb::io::Archive {
public:
    // What io::Archive::write does for grids with unique, non-empty names and no shared trees,
    // with grid i made by make(i) just before it is written and dropped after: one grid at a
    // time is held as an OpenVDB tree.
    template <typename Make>
    void save(std::ostream &os, int ngrids, const Make &make, const openvdb::MetaMap &meta, bool seekable) const
    {
        openvdb::io::StreamMetadata::Ptr sm(new openvdb::io::StreamMetadata);
        openvdb::io::setStreamMetadataPtr(os, sm, /*transfer=*/false);
        openvdb::io::setDataCompression(os, compression());
        openvdb::io::setWriteGridStatsMetadata(os, isGridStatsMetadataEnabled());
        writeHeader(os, seekable);
        meta.writeMeta(os);
        int32_t count = ngrids;
        os.write(reinterpret_cast<const char *>(&count), sizeof count);
        for (int i = 0; i < ngrids; ++i) {
            GridBase::Ptr grid = make(i);
            openvdb::io::GridDescriptor gd(grid->getName(), grid->type(), grid->saveFloatAsHalf());
            writeGrid(gd, grid, os, seekable);
            openvdb::io::setDataCompression(os, compression()); // mask compression is set per grid
        }
    }

    // Grids come out in file order; *count receives the number of grids the file holds. With
    // grid offsets, the wanted grids are read on up to `threads` threads, each with its own
    // stream on the file (descriptor fd).
    template <typename Want>
    void load(std::istream &is, int fd, int64_t fsize, const Want &want, int threads, hv_vdb_cancel_fn cancel,
              openvdb::GridPtrVec &out, openvdb::MetaMap &meta, int32_t *count)
    {
        using openvdb::io::GridDescriptor;
        readHeader(is);
        tag(is);
        meta.readMeta(is);
        *count = readGridCount(is);
        if (*count < 0) damaged("a negative grid count");
        const bool offsets = inputHasGridOffsets();
        std::vector<GridDescriptor> taken;
        std::vector<GridBase::Ptr> grids;
        std::map<openvdb::Name, GridDescriptor> skipped; // by unique name, for instance parents
        for (int32_t i = 0; i < *count; ++i) {
            GridDescriptor gd;
            GridBase::Ptr grid = gd.read(is);
            const int64_t at = int64_t(is.tellg());
            if (offsets && gd.getGridPos() != at)
                damaged("grid '" + one_line(gd.gridName()) + "' does not start where its offset says (byte " +
                        std::to_string(gd.getGridPos()) + ", not " + std::to_string(at) + ")");
            if (offsets && (gd.getEndPos() < at || gd.getEndPos() > fsize))
                damaged("grid '" + one_line(gd.gridName()) + "' ends at byte " + std::to_string(gd.getEndPos()) +
                        ", outside bytes " + std::to_string(at) + " to " + std::to_string(fsize));
            if (offsets) { // the grid itself is read below (or not at all)
                if (want(gd.gridName())) {
                    taken.push_back(gd);
                    grids.push_back(grid);
                } else {
                    skipped[gd.uniqueName()] = gd;
                }
                is.seekg(gd.getEndPos(), std::ios_base::beg);
                continue;
            }
            Archive::readGrid(grid, gd, is);
            taken.push_back(gd);
            grids.push_back(grid);
        }
        if (offsets) read_grids(is, fd, taken, grids, threads, cancel);
        NamedGridMap named;
        for (size_t i = 0; i < taken.size(); ++i) named[taken[i].uniqueName()] = grids[i];
        // an instance shares its parent's tree: a parent skipped above is read now
        for (const GridDescriptor &gd : taken) {
            if (!gd.isInstance() || named.count(gd.instanceParentName())) continue;
            auto it = skipped.find(gd.instanceParentName());
            if (it == skipped.end()) continue; // connectInstance names the missing parent
            GridBase::Ptr parent = GridBase::createGrid(it->second.gridType());
            parent->setSaveFloatAsHalf(it->second.saveFloatAsHalf());
            is.seekg(it->second.getGridPos(), std::ios_base::beg);
            Archive::readGrid(parent, it->second, is);
            named[it->second.uniqueName()] = parent;
        }
        for (const GridDescriptor &gd : taken) connectInstance(gd, named);
        for (size_t i = 0; i < taken.size(); ++i)
            if (offsets || want(taken[i].gridName())) out.push_back(grids[i]);
    }

private:
    // Tag a stream as io::Stream tags the file's: format and library version, compression.
    void tag(std::istream &is) const
    {
        mTags.emplace_back(new openvdb::io::StreamMetadata);
        openvdb::io::setStreamMetadataPtr(is, mTags.back(), /*transfer=*/false);
        openvdb::io::setVersion(is, libraryVersion(), fileVersion());
        openvdb::io::setDataCompression(is, compression());
    }

    // One grid from its offsets; it must end where its descriptor says.
    static void read_one(std::istream &is, const openvdb::io::GridDescriptor &gd, const GridBase::Ptr &grid)
    {
        is.seekg(gd.getGridPos(), std::ios_base::beg);
        Archive::readGrid(grid, gd, is);
        if (int64_t(is.tellg()) != gd.getEndPos())
            damaged("grid '" + one_line(gd.gridName()) + "' does not end where its offset says");
    }

    // The grids of a file with offsets, largest first on each free thread; the failure of the
    // grid first in the file is the one reported, whatever the threads' timing.
    void read_grids(std::istream &is, int fd, const std::vector<openvdb::io::GridDescriptor> &gds,
                    const std::vector<GridBase::Ptr> &grids, int threads, hv_vdb_cancel_fn cancel) const
    {
        const size_t n = gds.size();
        if (threads > int(n)) threads = int(n);
        if (threads <= 1) {
            for (size_t i = 0; i < n; ++i) read_one(is, gds[i], grids[i]);
            return;
        }
        std::vector<size_t> order(n);
        for (size_t i = 0; i < n; ++i) order[i] = i;
        std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
            return gds[a].getEndPos() - gds[a].getGridPos() > gds[b].getEndPos() - gds[b].getGridPos();
        });
        std::vector<std::exception_ptr> errors(n);
        std::atomic<size_t> next(0);
        auto work = [&](std::istream &s) {
            for (size_t k; (k = next.fetch_add(1)) < n;) {
                const size_t i = order[k];
                try {
                    read_one(s, gds[i], grids[i]);
                } catch (...) {
                    errors[i] = std::current_exception();
                    next.store(n); // the load fails: stop handing out grids
                }
            }
        };
        std::vector<std::unique_ptr<ReadBuf>> bufs;
        std::vector<std::unique_ptr<std::istream>> streams;
        for (int t = 1; t < threads; ++t) {
            bufs.emplace_back(new ReadBuf(cancel, fd));
            streams.emplace_back(new std::istream(bufs.back().get()));
            streams.back()->exceptions(std::ios::failbit | std::ios::badbit);
            tag(*streams.back());
        }
        std::vector<std::thread> pool;
        try {
            for (auto &s : streams) pool.emplace_back(work, std::ref(*s));
        } catch (...) { // no thread to be had: this one reads the rest
        }
        work(is);
        for (auto &t : pool) t.join();
        for (auto &e : errors)
            if (e) std::rethrow_exception(e);
    }

    // setStreamMetadataPtr keeps the address of the shared pointer itself: a deque never moves it
    mutable std::deque<openvdb::io::StreamMetadata::Ptr> mTags;

    [[noreturn]] static void damaged(const std::string &what) { throw Damaged{what + ": the file is damaged"}; }
};

// Grid g of a save, built from hovox's leaf tables. Inactive values are meaningless to hovox but
// visible to other readers: they are written as 0.
template <typename GridT>
GridBase::Ptr build_grid(const openvdb::math::Transform::Ptr &xf, size_t n, const int32_t *origins,
                         const uint64_t *masks, const void *const *buffers)
{
    typename GridT::Ptr grid = GridT::create(typename GridT::ValueType(0));
    grid->setTransform(xf);
    auto &tree = grid->tree();
    for (size_t l = 0; l < n; ++l) {
        auto *leaf = tree.touchLeaf(Coord(origins[3 * l], origins[3 * l + 1], origins[3 * l + 2]));
        const uint64_t *m = masks + 8 * l;
        auto &vm = leaf->getValueMask();
        for (int w = 0; w < 8; ++w) vm.template getWord<uint64_t>(w) = m[w];
        if constexpr (std::is_same<typename GridT::ValueType, bool>::value) {
            const uint64_t *src = static_cast<const uint64_t *>(buffers[l]);
            uint64_t *dst = leaf->buffer().data();
            for (int w = 0; w < 8; ++w) dst[w] = src[w] & m[w];
        } else {
            const float *src = static_cast<const float *>(buffers[l]);
            float *dst = leaf->buffer().data();
            for (unsigned i = 0; i < 512; ++i) dst[i] = (m[i >> 6] >> (i & 63)) & 1 ? src[i] : 0.0f;
        }
    }
    return grid;
}

int b_save(const char *path, const double voxel[3], const double origin[3], size_t n, const int32_t *origins,
           const uint64_t *masks, int ngrids, const char *const *names, const int *types, const unsigned char *half,
           const void *const *const *buffers, int nmeta, const char *const *keys, const int *kinds,
           const char *const *strings, const double *numbers, hv_vdb_cancel_fn cancel)
{
    try {
        const openvdb::math::Transform::Ptr xf = make_transform(voxel, origin);
        auto make = [&](int g) {
            GridBase::Ptr gp = types[g] == T_FLOAT ? build_grid<FloatGrid>(xf, n, origins, masks, buffers[g])
                                                   : build_grid<BoolGrid>(xf, n, origins, masks, buffers[g]);
            gp->setSaveFloatAsHalf(types[g] == T_FLOAT && half[g] != 0);
            gp->setName(names[g]);
            gp->insertMeta("hovox.index", openvdb::Int32Metadata(g)); // files list grids by name
            if (cancel && cancel()) throw Cancelled{};
            return gp;
        };
        openvdb::MetaMap meta;
        for (int i = 0; i < nmeta; ++i) {
            if (kinds[i] == HV_META_NUMBER)
                meta.insertMeta(keys[i], openvdb::DoubleMetadata(numbers[i]));
            else
                meta.insertMeta(keys[i], openvdb::StringMetadata(strings[i]));
        }
        // our own stream, every write checked (io::File does not report a full disk)
        CheckedBuf buf(cancel);
        if (!buf.open(path, std::ios::out | std::ios::binary | std::ios::trunc))
            return fail(E_IO, std::string("cannot open for writing: ") + std::strerror(errno));
        std::ostream os(&buf);
        os.exceptions(std::ios::failbit | std::ios::badbit);
        // offsets need seeking back: a device or FIFO (hovox writes /dev/null in place) gets
        // io::Stream's format
        struct stat st;
        const bool seekable = !(stat(path, &st) == 0 && !S_ISREG(st.st_mode));
        HvArchive().save(os, ngrids, make, meta, seekable);
        os.flush();
        if (!buf.close()) return fail(E_IO, "closing the file failed (disk full?)");
        return OK;
    }
    catch (const Cancelled &) { return fail(E_CANCELLED, "cancelled"); }
    catch (const std::ios_base::failure &) { return fail(E_IO, std::string("write failed (disk full?)")); }
    catch (const std::bad_alloc &) { return fail(E_NOMEM, "out of memory"); }
    catch (const std::exception &e) { return fail(E_IO, one_line(e.what())); }
    catch (...) { return fail(E_IO, "unknown exception writing the file"); }
}

// Convert any supported grid to FloatGrid or BoolGrid with tiles expanded.
GridBase::Ptr convert_grid(const GridBase::Ptr &in, int *type)
{
    GridBase::Ptr out;
    if (auto f = openvdb::gridPtrCast<FloatGrid>(in)) {
        out = f;
        *type = T_FLOAT;
    } else if (auto d = openvdb::gridPtrCast<openvdb::DoubleGrid>(in)) {
        FloatGrid::Ptr c = FloatGrid::create(FloatGrid::TreeType::Ptr(
            new FloatGrid::TreeType(d->tree(), float(d->background()), openvdb::TopologyCopy())));
        for (auto it = c->tree().beginLeaf(); it; ++it) {
            const auto *src = d->tree().probeConstLeaf(it->origin());
            for (openvdb::Index n = 0; n < FloatGrid::TreeType::LeafNodeType::SIZE; ++n)
                it->setValueOnly(n, float(src->getValue(n)));
        }
        out = c;
        *type = T_FLOAT;
    } else if (auto i = openvdb::gridPtrCast<openvdb::Int32Grid>(in)) {
        FloatGrid::Ptr c = FloatGrid::create(FloatGrid::TreeType::Ptr(
            new FloatGrid::TreeType(i->tree(), float(i->background()), openvdb::TopologyCopy())));
        for (auto it = c->tree().beginLeaf(); it; ++it) {
            const auto *src = i->tree().probeConstLeaf(it->origin());
            for (openvdb::Index n = 0; n < FloatGrid::TreeType::LeafNodeType::SIZE; ++n)
                it->setValueOnly(n, float(src->getValue(n)));
        }
        out = c;
        *type = T_FLOAT;
    } else if (auto b = openvdb::gridPtrCast<BoolGrid>(in)) {
        out = b;
        *type = T_BOOL;
    } else if (auto m = openvdb::gridPtrCast<MaskGrid>(in)) {
        BoolGrid::Ptr c = BoolGrid::create(BoolGrid::TreeType::Ptr(
            new BoolGrid::TreeType(m->tree(), false, true, openvdb::TopologyCopy())));
        out = c;
        *type = T_BOOL;
    } else {
        throw openvdb::TypeError("grid '" + in->getName() + "' has unsupported type " +
                                 in->type() + " (hovox reads float, double, int32, bool, mask)");
    }
    if (*type == T_FLOAT) {
        auto f = openvdb::gridPtrCast<FloatGrid>(out);
        f->tree().voxelizeActiveTiles();
        f->setSaveFloatAsHalf(false);
    } else {
        openvdb::gridPtrCast<BoolGrid>(out)->tree().voxelizeActiveTiles();
    }
    return out;
}

bool axis_aligned(const openvdb::math::Transform &xf, double voxel[3], double origin[3])
{
    if (!xf.isLinear()) return false;
    openvdb::math::Mat4d m = xf.baseMap()->getAffineMap()->getMat4();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            if (r != c && std::fabs(m(r, c)) > 1e-12 * std::fabs(m(r, r))) return false;
    for (int a = 0; a < 3; ++a) {
        voxel[a] = m(a, a);
        origin[a] = m(3, a);
        if (!(voxel[a] > 0) || !std::isfinite(voxel[a]) || !std::isfinite(origin[a])) return false;
    }
    return true;
}

// Bytes hovox needs for grid g once its active tiles are expanded into leaves, estimated from
// the tree's structure alone (nothing is expanded yet).
uint64_t expanded_bytes(const GridBase &g, uint64_t *voxels)
{
    *voxels = g.activeVoxelCount();
    const uint64_t leaves = (*voxels + 511) / 512 + g.baseTree().leafCount();
    const bool bits = g.isType<BoolGrid>() || g.isType<MaskGrid>();
    // OpenVDB's expanded leaf, and hovox's copy of it, which exists at the same time while the grid
    // is copied into the store (measured: a 512^3-voxel tile grid peaks at 1.9 times OpenVDB's
    // own), plus the shared topology and hovox's leaf tables
    const uint64_t per_leaf = bits ? 200 + 64 : 2200 + 2048;
    return leaves * (per_leaf + 200);
}

// Does `name` match one of the n selectors (a name, or a prefix followed by '*')? n < 0: all.
bool selected(const std::string &name, const char *const *want, int n)
{
    if (n < 0) return true;
    for (int i = 0; i < n; ++i) {
        size_t len = std::strlen(want[i]);
        if (len && want[i][len - 1] == '*' ? name.compare(0, len - 1, want[i], len - 1) == 0 : name == want[i])
            return true;
    }
    return false;
}

// Every grid within the budget once expanded (max_bytes, 0: none) and within index 2^30; a
// failure code (fail()) or OK.
int check_grids(const openvdb::GridPtrVec &grids, uint64_t max_bytes)
{
    uint64_t total = 0;
    for (const auto &g : grids) {
        uint64_t voxels = 0, bytes = expanded_bytes(*g, &voxels);
        total += bytes;
        if (max_bytes && total > max_bytes)
            return fail(E_LIMIT, "grid '" + one_line(g->getName()) + "' holds " + std::to_string(voxels) +
                                     " active voxels: about " + size_text(double(total)) +
                                     " once expanded, more than the budget of " +
                                     size_text(double(max_bytes)));
        const openvdb::CoordBBox bb = g->evalActiveVoxelBoundingBox();
        const int lim = 1 << 30;
        if (!bb.empty() && (bb.min().x() < -lim || bb.min().y() < -lim || bb.min().z() < -lim ||
                            bb.max().x() > lim || bb.max().y() > lim || bb.max().z() > lim))
            return fail(E_BAD_INPUT, "grid '" + one_line(g->getName()) + "' has voxels beyond index 2^30");
    }
    return OK;
}

// The grids' one axis-aligned lattice (voxel size and origin into v0, o0); a failure code when a
// grid has another transform.
int common_lattice(const openvdb::GridPtrVec &grids, double v0[3], double o0[3])
{
    for (size_t i = 0; i < grids.size(); ++i) {
        const GridBase::Ptr &g = grids[i];
        double vs[3], os[3];
        if (!axis_aligned(g->transform(), vs, os))
            return fail(E_BAD_INPUT, "grid '" + g->getName() +
                                         "' has a transform that is not an axis-aligned scale "
                                         "and translation");
        if (i == 0) {
            std::memcpy(v0, vs, sizeof vs);
            std::memcpy(o0, os, sizeof os);
            continue;
        }
        for (int a = 0; a < 3; ++a)
            if (std::fabs(vs[a] - v0[a]) > 1e-9 * v0[a] || std::fabs(os[a] - o0[a]) > 1e-9 * v0[a])
                return fail(E_BAD_INPUT, "grid '" + g->getName() + "' has a different transform from grid '" +
                                             grids[0]->getName() + "'");
    }
    return OK;
}

// The file's metadata to the caller, one entry at a time; the first nonzero answer of meta_cb.
int pass_metadata(const openvdb::MetaMap &meta, hv_vdb_meta_cb meta_cb, void *ctx)
{
    for (auto it = meta.beginMeta(); it != meta.endMeta(); ++it) {
        const openvdb::Metadata::ConstPtr m = it->second;
        int rc = 0;
        if (m->typeName() == openvdb::StringMetadata::staticTypeName())
            rc = meta_cb(ctx, it->first.c_str(), HV_META_STRING,
                         static_cast<const openvdb::StringMetadata &>(*m).value().c_str(), 0.0);
        else if (m->typeName() == openvdb::DoubleMetadata::staticTypeName())
            rc = meta_cb(ctx, it->first.c_str(), HV_META_NUMBER, nullptr,
                         static_cast<const openvdb::DoubleMetadata &>(*m).value());
        else if (m->typeName() == openvdb::FloatMetadata::staticTypeName())
            rc = meta_cb(ctx, it->first.c_str(), HV_META_NUMBER, nullptr,
                         static_cast<const openvdb::FloatMetadata &>(*m).value());
        else if (m->typeName() == openvdb::Int32Metadata::staticTypeName())
            rc = meta_cb(ctx, it->first.c_str(), HV_META_NUMBER, nullptr,
                         static_cast<const openvdb::Int32Metadata &>(*m).value());
        else if (m->typeName() == openvdb::Int64Metadata::staticTypeName())
            rc = meta_cb(ctx, it->first.c_str(), HV_META_NUMBER, nullptr,
                         double(static_cast<const openvdb::Int64Metadata &>(*m).value()));
        else
            rc = meta_cb(ctx, it->first.c_str(), HV_META_STRING, m->str().c_str(), 0.0);
        if (rc != 0) return rc;
    }
    return 0;
}

int b_load(const char *path, const char *const *want, int nwant, int threads, void **out, double voxel[3],
           double origin[3], hv_vdb_meta_cb meta_cb, hv_vdb_grid_cb grid_cb, void *ctx, uint64_t max_bytes,
           hv_vdb_cancel_fn cancel)
{
    Volume *v = nullptr;
    try {
        // our own stream with every read checked: a file that ends early throws at once,
        // instead of OpenVDB reading on with garbage counts
        QuietStreams quiet;
        ReadBuf buf(cancel);
        if (!buf.open(path)) return fail(E_IO, std::string("cannot open: ") + std::strerror(errno));
        const uint32_t version = file_version(path);
        if (version > openvdb::OPENVDB_FILE_VERSION)
            return fail(E_BAD_INPUT, "file format version " + std::to_string(version) + " is newer than this " +
                                         "OpenVDB reads (" + std::to_string(openvdb::OPENVDB_FILE_VERSION) +
                                         "): the file is damaged or from a later OpenVDB");
        std::istream is(&buf);
        is.exceptions(std::ios::failbit | std::ios::badbit);
        struct stat st;
        uint64_t fsize = fstat(buf.fd(), &st) == 0 ? uint64_t(st.st_size) : 0;
        openvdb::GridPtrVecPtr grids(new openvdb::GridPtrVec);
        openvdb::MetaMap::Ptr meta(new openvdb::MetaMap);
        int32_t count = 0;
        try {
            AddressLimit limit((uint64_t(256) << 20) + 64 * fsize); // trees in memory: about the file's size; a damaged length asking for more fails at once instead of being filled
            HvArchive().load(is, buf.fd(), int64_t(fsize), [&](const std::string &name) { return selected(name, want, nwant); },
                             threads, cancel, *grids, *meta, &count);
        } catch (const std::bad_alloc &) {
            return fail(E_BAD_INPUT, "the file is damaged: it asks for more memory than its " + std::to_string(fsize) +
                                         " bytes can hold");
        }
        if (count == 0) return fail(E_BAD_INPUT, "file holds no grids");
        if (int rc = check_grids(*grids, max_bytes)) return rc;
        // restore hovox's grid order (OpenVDB returns grids by name)
        std::stable_sort(grids->begin(), grids->end(), [](const GridBase::Ptr &a, const GridBase::Ptr &b) {
            auto ia = a->getMetadata<openvdb::Int32Metadata>("hovox.index");
            auto ib = b->getMetadata<openvdb::Int32Metadata>("hovox.index");
            int x = ia ? ia->value() : INT32_MAX, y = ib ? ib->value() : INT32_MAX;
            return x < y;
        });
        double v0[3] = {1, 1, 1}, o0[3] = {0, 0, 0}; // no grid selected: the unit lattice
        if (int rc = common_lattice(*grids, v0, o0)) return rc;
        v = new Volume;
        v->xf = make_transform(v0, o0);
        v->topo = MaskGrid::create(false);
        v->topo->setTransform(v->xf);
        for (const auto &g : *grids) {
            int type = 0;
            const int half = g->saveFloatAsHalf() ? HV_VDB_HALF : 0; // convert_grid clears it
            GridBase::Ptr c = convert_grid(g, &type);
            c->setTransform(v->xf);
            if (type == T_FLOAT)
                v->topo->tree().topologyUnion(openvdb::gridPtrCast<FloatGrid>(c)->tree());
            else
                v->topo->tree().topologyUnion(openvdb::gridPtrCast<BoolGrid>(c)->tree());
            v->grids.push_back(c);
            if (grid_cb(ctx, g->getName().c_str(), type | half) != 0) {
                delete v;
                return fail(E_NOMEM, "out of memory");
            }
        }
        v->topo->tree().voxelizeActiveTiles();
        for (auto &g : v->grids) match_topology(*v, *g);
        if (meta && pass_metadata(*meta, meta_cb, ctx) != 0) {
            delete v;
            return fail(E_NOMEM, "out of memory");
        }
        std::memcpy(voxel, v0, sizeof v0);
        std::memcpy(origin, o0, sizeof o0);
        *out = v;
        return OK;
    }
    catch (const Cancelled &) { delete v; return fail(E_CANCELLED, "cancelled"); }
    catch (const Damaged &e) { delete v; return fail(E_BAD_INPUT, e.what); }
    catch (const std::ios_base::failure &) {
        delete v;
        return fail(E_BAD_INPUT, "the file ends early or is damaged (a read failed)");
    }
    catch (const std::bad_alloc &) { delete v; return fail(E_NOMEM, "out of memory"); }
    catch (const openvdb::TypeError &e) { /* a grid hovox does not read (convert_grid) */
        delete v;
        std::string m = one_line(e.what());
        return fail(E_BAD_INPUT, m.rfind("TypeError: ", 0) == 0 ? m.substr(11) : m);
    }
    catch (const std::exception &e) {
        delete v;
        return fail(E_BAD_INPUT, "damaged or not an OpenVDB file (" + one_line(e.what()) + ")");
    }
    catch (...) { delete v; return fail(E_BAD_INPUT, "unknown exception reading VDB file"); }
}


/* ---- surfaces of a Boolean tree (issue 28): a narrow-band level set per leaf mesh, OpenVDB's CSG
 * per node, volumeToMesh (adaptivity 0) of the root ---------------------------------------- */
struct CancelPoll : openvdb::util::NullInterrupter {
    hv_vdb_cancel_fn cancel;
    explicit CancelPoll(hv_vdb_cancel_fn c) : cancel(c) {}
    bool wasInterrupted(int = -1) override { return cancel && cancel(); }
};

int b_surface(int nleaf, const float *const *xyz, const size_t *nv, const uint32_t *const *tri, const size_t *nt,
              int nnode, const int *ops, const uint32_t *leaf, const uint32_t *na, const uint32_t *nb, double voxel,
              float **out_xyz, size_t *out_nv, uint32_t **out_tri, size_t *out_nt, hv_vdb_cancel_fn cancel)
{
    using openvdb::FloatGrid;
    *out_xyz = nullptr;
    *out_tri = nullptr;
    *out_nv = *out_nt = 0;
    try {
        CancelPoll poll(cancel);
        auto xf = openvdb::math::Transform::createLinearTransform(voxel);
        std::vector<int> uses((size_t)nnode, 0);
        for (int i = 0; i < nnode; ++i)
            if (ops[i] >= 0) {
                if (na[i] >= (uint32_t)i || nb[i] >= (uint32_t)i) return fail(E_BAD_INPUT, "tree node out of order");
                uses[na[i]]++;
                uses[nb[i]]++;
            } else if (leaf[i] >= (uint32_t)nleaf) {
                return fail(E_BAD_INPUT, "tree refers to a missing leaf");
            }
        std::vector<FloatGrid::Ptr> node((size_t)nnode);
        /* a child's grid: moved out at its last use, else a copy (CSG empties its operands) */
        auto take = [&](uint32_t k) {
            return --uses[k] == 0 ? std::move(node[k]) : node[k]->deepCopy();
        };
        for (int i = 0; i < nnode; ++i) {
            if (ops[i] < 0) {
                uint32_t l = leaf[i];
                std::vector<openvdb::Vec3s> pts(nv[l]);
                std::vector<openvdb::Vec3I> tris(nt[l]);
                for (size_t v = 0; v < nv[l]; ++v) pts[v] = openvdb::Vec3s(xyz[l][3 * v], xyz[l][3 * v + 1], xyz[l][3 * v + 2]);
                for (size_t t = 0; t < nt[l]; ++t) tris[t] = openvdb::Vec3I(tri[l][3 * t], tri[l][3 * t + 1], tri[l][3 * t + 2]);
                node[i] = openvdb::tools::meshToLevelSet<FloatGrid>(poll, *xf, pts, tris, 3.0f);
            } else {
                FloatGrid::Ptr a = take(na[i]), b = take(nb[i]);
                switch (ops[i]) {
                case 0: openvdb::tools::csgIntersection(*a, *b); break;
                case 1:
                case 3: openvdb::tools::csgUnion(*a, *b); break;
                case 2: break; /* Wu's difference keeps O1's shape */
                case 4: openvdb::tools::csgDifference(*a, *b); break;
                default: return fail(E_BAD_INPUT, "unknown Boolean " + std::to_string(ops[i]));
                }
                node[i] = std::move(a);
            }
            if (poll.wasInterrupted()) return fail(E_CANCELLED, "cancelled");
        }
        std::vector<openvdb::Vec3s> points;
        std::vector<openvdb::Vec3I> tris;
        std::vector<openvdb::Vec4I> quads;
        openvdb::tools::volumeToMesh(*node[(size_t)nnode - 1], points, tris, quads, 0.0, 0.0);
        size_t n = tris.size() + 2 * quads.size();
        float *p = static_cast<float *>(std::malloc(3 * sizeof(float) * (points.size() ? points.size() : 1)));
        uint32_t *t = static_cast<uint32_t *>(std::malloc(3 * sizeof(uint32_t) * (n ? n : 1)));
        if (!p || !t) {
            std::free(p);
            std::free(t);
            return fail(E_NOMEM, "out of memory");
        }
        for (size_t v = 0; v < points.size(); ++v)
            for (int k = 0; k < 3; ++k) p[3 * v + k] = points[v][k];
        size_t m = 0;
        for (const auto &q : tris)
            for (int k = 0; k < 3; ++k) t[m++] = q[k];
        for (const auto &q : quads) {
            const uint32_t c[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
            for (uint32_t k : c) t[m++] = k;
        }
        *out_xyz = p;
        *out_nv = points.size();
        *out_tri = t;
        *out_nt = n;
        return 0;
    }
    catch (const std::bad_alloc &) { return fail(E_NOMEM, "out of memory"); }
    catch (const std::exception &e) { return fail(E_BAD_INPUT, one_line(e.what())); }
    catch (...) { return fail(E_BAD_INPUT, "unknown exception making the surface"); }
}

/* ---- threads: hovox's count (hv_threads(), --threads) as TBB's limit for all OpenVDB runs here
 * (meshToLevelSet, the CSG, volumeToMesh, the trees' reductions on save); without it TBB took
 * every processor of the affinity mask whatever --threads said. Kept (not freed) until the count
 * changes: a global_control lives as long as its limit should. */
std::mutex g_threads_mutex;
tbb::global_control *g_threads_limit = nullptr;
int g_threads_n = 0;

int b_threads(int n)
{
    if (n < 1) n = 1;
    try {
        std::lock_guard<std::mutex> lock(g_threads_mutex);
        if (n == g_threads_n) return 0;
        delete g_threads_limit;
        g_threads_limit = nullptr;
        g_threads_n = 0;
        g_threads_limit = new tbb::global_control(tbb::global_control::max_allowed_parallelism, size_t(n));
        g_threads_n = n;
        return 0;
    }
    HV_CATCH_PREFIXED(E_NOMEM, "thread limit: ", "OpenVDB")
}

const hv_vdb_api g_api = {
    HV_VDB_ABI,   b_last_error,    b_save,         b_load,      b_leaf_count,
    b_leaf_topology, b_leaf_buffers, b_grid_free, b_destroy, b_surface, b_threads,
};

} // namespace

extern "C" __attribute__((visibility("default"))) const hv_vdb_api *hv_vdb_plugin_v1(void)
{
    static std::once_flag once;
    static bool ok = false;
    std::call_once(once, [] {
        try {
            openvdb::initialize();
            ok = true;
        } catch (...) {
            ok = false;
        }
    });
    return ok ? &g_api : nullptr;
}
