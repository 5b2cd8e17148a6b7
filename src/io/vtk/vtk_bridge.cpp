// src/export/vtk_bridge.cpp - the only code that includes VTK: writes .vti image data and .vtu
// hexahedral meshes (XML, appended raw binary, zlib, 64-bit headers) from plain arrays the C
// exporter (src/export) built. Built as plugins/hovox-vtk.so and loaded only when exporting.
// Every entry catches all exceptions (HV_CATCH) and turns them into a status plus what();
// VTK's own error text is captured (never printed: the library does not print).
#include "vtk_bridge.h"

#include "core/bridge.hpp"

#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLImageDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>
#include <vtkDataArray.h>
#include <vtkPolyData.h>
#include <vtkProbeFilter.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cctype>
#include <cstdio>

#include <climits>
#include <mutex>
#include <new>
#include <stdexcept>
#include <string>

namespace {

using namespace hv_bridge;

#define HV_CATCH(code) HV_CATCH_PREFIXED(code, "VTK: ", "VTK")


// VTK reports errors through vtkOutputWindow, which prints. Keep the text instead: the C side
// turns it into the error message of the failing call.
class CaptureWindow : public vtkOutputWindow {
public:
    static CaptureWindow *New();
    vtkTypeMacro(CaptureWindow, vtkOutputWindow);
    void DisplayText(const char *text) override { keep(text); }
    void DisplayErrorText(const char *text) override { keep(text); }
    void DisplayWarningText(const char *) override {}
    void DisplayGenericWarningText(const char *) override {}
    void DisplayDebugText(const char *) override {}
    static std::string take()
    {
        std::string s = t_last;
        t_last.clear();
        return s;
    }
    static void keep(const char *text)
    {
        if (!text) return;
        t_last = text;
        // the message is "ERROR: In file, line N\nclass (ptr): text": keep the last line
        while (!t_last.empty() && (t_last.back() == '\n' || t_last.back() == ' ')) t_last.pop_back();
        size_t nl = t_last.rfind('\n');
        if (nl != std::string::npos) t_last = t_last.substr(nl + 1);
        size_t colon = t_last.find("): ");
        if (colon != std::string::npos) t_last = t_last.substr(colon + 3);
    }

private:
    static thread_local std::string t_last;
};
thread_local std::string CaptureWindow::t_last;
vtkStandardNewMacro(CaptureWindow);

struct WriteState {
    hv_vtk_progress_fn fn;
    void *user;
    bool cancelled;
    std::string error;
};

void on_progress(vtkObject *caller, unsigned long, void *client, void *call)
{
    WriteState *st = static_cast<WriteState *>(client);
    if (!st->fn || st->cancelled || !call) return;
    double f = *static_cast<double *>(call);
    if (st->fn(st->user, f) != 0) {
        st->cancelled = true;
        if (vtkAlgorithm *a = vtkAlgorithm::SafeDownCast(caller)) a->SetAbortExecute(1);
    }
}

void on_error(vtkObject *, unsigned long, void *client, void *call)
{
    WriteState *st = static_cast<WriteState *>(client);
    if (call && st->error.empty()) {
        CaptureWindow::keep(static_cast<const char *>(call));
        st->error = CaptureWindow::take();
    }
}

// A VTK array over the caller's buffer (no copy: the buffers outlive the write).
vtkSmartPointer<vtkAbstractArray> wrap(const hv_vtk_array &a)
{
    if (!a.name || a.components < 1 || a.tuples < 0)
        throw std::invalid_argument("bad array description");
    vtkIdType n = static_cast<vtkIdType>(a.tuples) * a.components;
    vtkSmartPointer<vtkAbstractArray> out;
    switch (a.type) {
    case HV_VTK_UINT8: {
        auto arr = vtkSmartPointer<vtkUnsignedCharArray>::New();
        arr->SetNumberOfComponents(a.components);
        arr->SetArray(static_cast<unsigned char *>(const_cast<void *>(a.data)), n, 1);
        out = arr;
        break;
    }
    case HV_VTK_INT32: {
        auto arr = vtkSmartPointer<vtkIntArray>::New();
        arr->SetNumberOfComponents(a.components);
        arr->SetArray(static_cast<int *>(const_cast<void *>(a.data)), n, 1);
        out = arr;
        break;
    }
    case HV_VTK_FLOAT32: {
        auto arr = vtkSmartPointer<vtkFloatArray>::New();
        arr->SetNumberOfComponents(a.components);
        arr->SetArray(static_cast<float *>(const_cast<void *>(a.data)), n, 1);
        out = arr;
        break;
    }
    case HV_VTK_STRING: {
        auto arr = vtkSmartPointer<vtkStringArray>::New();
        arr->InsertNextValue(static_cast<const char *>(a.data));
        out = arr;
        break;
    }
    default: throw std::invalid_argument("unknown array type");
    }
    out->SetName(a.name);
    return out;
}

void add_field(vtkDataObject *d, const hv_vtk_write_opts *o)
{
    for (int i = 0; i < o->nfield; ++i) d->GetFieldData()->AddArray(wrap(o->field[i]));
}

// Settings of the issue: appended raw binary, zlib, 64-bit headers; then write and map the
// outcome to a status.
int run_writer(vtkXMLWriter *w, vtkDataObject *data, const char *path,
               const hv_vtk_write_opts *o)
{
    WriteState st{o->progress, o->user, false, std::string()};
    vtkNew<vtkCallbackCommand> prog, err;
    prog->SetCallback(on_progress);
    prog->SetClientData(&st);
    err->SetCallback(on_error);
    err->SetClientData(&st);
    w->AddObserver(vtkCommand::ProgressEvent, prog);
    w->AddObserver(vtkCommand::ErrorEvent, err);
    w->SetInputData(data);
    w->SetFileName(path);
    w->SetDataModeToAppended();
    w->EncodeAppendedDataOff();
    w->SetCompressorTypeToZLib();
    w->SetCompressionLevel(o->zlib_level >= 1 && o->zlib_level <= 9 ? o->zlib_level : 6);
    w->SetHeaderTypeToUInt64();
    // larger blocks than the 32 KiB default: fewer block headers, same memory order
    w->SetBlockSize(size_t(1) << 20);
    CaptureWindow::take();
    int ok = w->Write();
    unsigned long code = w->GetErrorCode();
    if (st.cancelled) return fail(E_CANCELLED, "cancelled");
    if (!ok || code != vtkErrorCode::NoError) {
        std::string msg = st.error.empty() ? CaptureWindow::take() : st.error;
        // (vtkErrorCode's names live in vtkCommonMisc, which the plugin does not link)
        if (code == vtkErrorCode::OutOfDiskSpaceError) msg = "out of disk space";
        else if (code == vtkErrorCode::CannotOpenFileError && msg.empty()) msg = "cannot open file";
        if (msg.empty()) msg = "error code " + std::to_string(code);
        return fail(E_IO, "VTK writer failed: " + msg);
    }
    return OK;
}

// --- entries --------------------------------------------------------------------------

const char *b_last_error() { return last_error(); }

int b_write_image(const char *path, const int64_t dims[3], const double origin[3],
                  const double spacing[3], int narrays, const hv_vtk_array *arrays,
                  const hv_vtk_write_opts *opts)
{
    try {
        for (int a = 0; a < 3; ++a)
            if (dims[a] < 1 || dims[a] > INT_MAX)
                return fail(E_LIMIT, "image dimension " + std::to_string(dims[a]) +
                                         " outside VTK's range [1, 2^31-1]");
        vtkNew<vtkImageData> img;
        img->SetDimensions(int(dims[0]), int(dims[1]), int(dims[2]));
        img->SetOrigin(origin[0], origin[1], origin[2]);
        img->SetSpacing(spacing[0], spacing[1], spacing[2]);
        int64_t n = dims[0] * dims[1] * dims[2];
        for (int i = 0; i < narrays; ++i) {
            if (arrays[i].tuples != n) return fail(E_INTERNAL, "point array size mismatch");
            img->GetPointData()->AddArray(wrap(arrays[i]));
        }
        add_field(img, opts);
        vtkNew<vtkXMLImageDataWriter> w;
        return run_writer(w, img, path, opts);
    }
    HV_CATCH(E_INTERNAL)
}

// Cells with 8 points each over the caller's connectivity (no copy); offsets 0, 8, 16, ...
template <typename ArrayT, typename IdT>
void set_hexes(vtkCellArray *cells, const void *connectivity, int64_t ncells)
{
    vtkNew<ArrayT> conn;
    conn->SetArray(static_cast<IdT *>(const_cast<void *>(connectivity)), vtkIdType(ncells) * 8, 1);
    vtkNew<ArrayT> offsets;
    offsets->SetNumberOfValues(vtkIdType(ncells) + 1);
    IdT *off = offsets->GetPointer(0);
    for (vtkIdType c = 0; c <= vtkIdType(ncells); ++c) off[c] = IdT(8 * c);
    cells->SetData(offsets, conn);
}

int b_write_hexes(const char *path, int64_t npoints, const float *points, int64_t ncells,
                  const void *connectivity, int conn64, int narrays, const hv_vtk_array *arrays,
                  const hv_vtk_write_opts *opts)
{
    try {
        if (!conn64 && (npoints > INT32_MAX || ncells > INT32_MAX / 8))
            return fail(E_INVALID, "32-bit connectivity for a mesh that needs 64-bit ids");
        vtkNew<vtkFloatArray> xyz;
        xyz->SetNumberOfComponents(3);
        xyz->SetArray(const_cast<float *>(points), vtkIdType(npoints) * 3, 1);
        vtkNew<vtkPoints> pts;
        pts->SetData(xyz);

        // 32-bit storage when the ids fit: half the memory and half the bytes to compress
        vtkNew<vtkCellArray> cells;
        if (conn64) set_hexes<vtkCellArray::ArrayType64, vtkTypeInt64>(cells, connectivity, ncells);
        else set_hexes<vtkCellArray::ArrayType32, vtkTypeInt32>(cells, connectivity, ncells);

        vtkNew<vtkUnstructuredGrid> grid;
        grid->SetPoints(pts);
        grid->SetCells(VTK_HEXAHEDRON, cells);
        for (int i = 0; i < narrays; ++i) {
            if (arrays[i].tuples != ncells) return fail(E_INTERNAL, "cell array size mismatch");
            grid->GetCellData()->AddArray(wrap(arrays[i]));
        }
        add_field(grid, opts);
        vtkNew<vtkXMLUnstructuredGridWriter> w;
        return run_writer(w, grid, path, opts);
    }
    HV_CATCH(E_INTERNAL)
}

// --- reading fields ---------------------------------------------------------------------

std::string array_names(vtkDataSet *ds)
{
    std::string s;
    vtkFieldData *fd[2] = {ds->GetPointData(), ds->GetCellData()};
    for (int k = 0; k < 2; ++k)
        for (int i = 0; i < fd[k]->GetNumberOfArrays(); ++i) {
            const char *n = fd[k]->GetArrayName(i);
            if (!n) continue;
            if (!s.empty()) s += ", ";
            s += n;
            s += k ? " (cell)" : " (point)";
        }
    return s.empty() ? "none" : s;
}

template <typename Reader>
vtkSmartPointer<vtkDataSet> read_xml(const char *path, std::string &err)
{
    vtkNew<Reader> r;
    if (!r->CanReadFile(path)) {
        err = "not a readable VTK XML file of this type";
        return nullptr;
    }
    r->SetFileName(path);
    r->Update();
    std::string captured = CaptureWindow::take();
    if (r->GetErrorCode() != 0 || !r->GetOutput() || !captured.empty()) {
        err = captured.empty() ? "VTK could not read it" : captured;
        return nullptr;
    }
    return vtkSmartPointer<vtkDataSet>(r->GetOutput());
}

int b_probe(const char *path, const char *array, int64_t n, const double *points, float *out, uint8_t *valid,
            hv_vtk_probe_info *info)
{
    try {
        std::string p(path), ext;
        size_t dot = p.rfind('.');
        if (dot != std::string::npos) ext = p.substr(dot);
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return (char)std::tolower(c); });
        if (FILE *f = std::fopen(path, "rb")) std::fclose(f);
        else return fail(E_IO, p + ": cannot open");
        std::string err;
        CaptureWindow::take();
        vtkSmartPointer<vtkDataSet> ds;
        if (ext == ".vti") ds = read_xml<vtkXMLImageDataReader>(path, err);
        else if (ext == ".vtu") ds = read_xml<vtkXMLUnstructuredGridReader>(path, err);
        else return fail(E_BAD_INPUT, p + ": not a .vti or .vtu file");
        if (!ds) return fail(E_BAD_INPUT, p + ": " + err);
        vtkDataArray *a = ds->GetPointData()->GetArray(array);
        info->cell_data = 0;
        if (!a) {
            a = ds->GetCellData()->GetArray(array);
            info->cell_data = 1;
        }
        if (!a) return fail(E_BAD_INPUT, p + ": no array '" + array + "' (arrays: " + array_names(ds) + ")");
        info->components = a->GetNumberOfComponents();
        info->points = ds->GetNumberOfPoints();
        info->cells = ds->GetNumberOfCells();
        if (info->components != 1)
            return fail(E_BAD_INPUT, p + ": array '" + array + "' has " + std::to_string(info->components) +
                                         " components; a field feature needs a scalar (1)");
        if (a->GetNumberOfTuples() == 0) return fail(E_BAD_INPUT, p + ": array '" + array + "' is empty");
        a->GetRange(info->range, 0);
        vtkNew<vtkPoints> pts;
        pts->SetDataTypeToDouble();
        pts->SetNumberOfPoints(vtkIdType(n));
        for (int64_t i = 0; i < n; ++i) pts->SetPoint(vtkIdType(i), points + 3 * i);
        vtkNew<vtkPolyData> where;
        where->SetPoints(pts);
        vtkNew<vtkProbeFilter> probe;
        probe->SetInputData(where);
        probe->SetSourceData(ds);
        probe->Update();
        vtkDataSet *o = probe->GetOutput();
        vtkDataArray *v = o ? o->GetPointData()->GetArray(array) : nullptr;
        vtkDataArray *m = o ? o->GetPointData()->GetArray(probe->GetValidPointMaskArrayName()) : nullptr;
        if (!v || !m || v->GetNumberOfTuples() != vtkIdType(n)) {
            std::string c = CaptureWindow::take();
            return fail(E_INTERNAL, p + ": probing failed" + (c.empty() ? "" : ": " + c));
        }
        for (int64_t i = 0; i < n; ++i) {
            valid[i] = m->GetTuple1(vtkIdType(i)) != 0;
            out[i] = valid[i] ? float(v->GetTuple1(vtkIdType(i))) : 0.0f;
        }
        return OK;
    }
    HV_CATCH(E_INTERNAL)
}

const hv_vtk_api g_api = {HV_VTK_ABI, b_last_error, b_write_image, b_write_hexes, b_probe};

} // namespace

extern "C" __attribute__((visibility("default"))) const hv_vtk_api *hv_vtk_plugin_v1(void)
{
    static std::once_flag once;
    static bool ok = false;
    std::call_once(once, [] {
        try {
            vtkNew<CaptureWindow> win;
            vtkOutputWindow::SetInstance(win);
            ok = true;
        } catch (...) {
            ok = false;
        }
    });
    return ok ? &g_api : nullptr;
}
