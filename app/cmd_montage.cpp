// stormlight montage: frames side by side in one PNG (contact sheets of series), through VTK.
#include <vtkImageAppend.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkSmartPointer.h>

#include <cstdio>
#include <string>
#include <vector>

#include "cli.h"
#include "commands.h"
#include "vtk_png.h"

int sl_cmd_montage(int argc, char **argv)
{
  sl::Options o("montage", "A.png B.png ... --out STRIP.png [--columns N]",
                "Places PNG frames of equal size in a grid, left to right and top to bottom.");
  o.option("out", "FILE.png", "output PNG");
  o.option("columns", "N", "frames per row (0 = all in one row)", "0");
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;
  const std::string cmd = "montage";
  if (o.positional().empty()) return sl::fail(cmd, "give at least one PNG frame", 2);
  if (!o.has("out")) return sl::fail(cmd, "missing --out FILE.png", 2);
  long columns;
  if (!o.integer("columns", &columns, 0, 10000)) return sl::fail(cmd, o.error(), 2);
  const int n = (int)o.positional().size();
  if (columns == 0) columns = n;
  std::vector<vtkSmartPointer<vtkImageData>> frames;
  int dims[3] = {0, 0, 0}, comps = 0;
  for (const std::string &f : o.positional()) {
    vtkNew<vtkPNGReader> reader;
    if (!reader->CanReadFile(f.c_str())) return sl::fail(cmd, f + ": not a readable PNG file");
    reader->SetFileName(f.c_str());
    reader->Update();
    vtkSmartPointer<vtkImageData> img = reader->GetOutput();
    int d[3];
    img->GetDimensions(d);
    if (frames.empty()) {
      dims[0] = d[0], dims[1] = d[1], comps = img->GetNumberOfScalarComponents();
    } else if (d[0] != dims[0] || d[1] != dims[1] || img->GetNumberOfScalarComponents() != comps) {
      return sl::fail(cmd, f + ": size or channels differ from the first frame");
    }
    frames.push_back(img);
  }
  // Rows are appended bottom-up (VTK's images start at the bottom), the last row padded black.
  const int rows = (int)((n + columns - 1) / columns);
  vtkNew<vtkImageAppend> vertical;
  vertical->SetAppendAxis(1);
  for (int r = rows - 1; r >= 0; --r) {
    vtkNew<vtkImageAppend> row;
    row->SetAppendAxis(0);
    for (int c = 0; c < columns; ++c) {
      const int i = r * (int)columns + c;
      if (i < n) {
        row->AddInputData(frames[i]);
      } else {
        vtkNew<vtkImageData> black;
        black->SetDimensions(dims[0], dims[1], 1);
        black->AllocateScalars(frames[0]->GetScalarType(), comps);
        std::fill_n(static_cast<unsigned char *>(black->GetScalarPointer()), (size_t)dims[0] * dims[1] * comps, 0);
        row->AddInputData(black);
      }
    }
    row->Update();
    vtkNew<vtkImageData> copy;
    copy->DeepCopy(row->GetOutput());
    vertical->AddInputData(copy);
  }
  vertical->Update();
  std::string why;
  if (!sl::write_png(vertical->GetOutput(), o.str("out"), &why)) return sl::fail(cmd, why);
  return 0;
}
