// SPDX-License-Identifier: MIT
#include "deepcut/widgets/texture.h"

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkImageData.h>
#include <vtkImageFlip.h>
#include <vtkImageReader2.h>
#include <vtkJPEGReader.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include <string>

#include "deepcut/core/errors.h"

namespace deepcut {
namespace {

bool starts_with(const std::vector<unsigned char>& data, std::initializer_list<unsigned char> magic) {
  if (data.size() < magic.size()) return false;
  std::size_t i = 0;
  for (unsigned char m : magic)
    if (data[i++] != m) return false;
  return true;
}

/// Records that the reader reported an error, instead of letting VTK print it.
void note_error(vtkObject*, unsigned long, void* client_data, void*) {
  *static_cast<bool*>(client_data) = true;
}

}  // namespace

vtkSmartPointer<vtkTexture> make_texture(const Image& image) {
  const std::string what = "image '" + (image.name.empty() ? std::string("(unnamed)") : image.name) + "'";
  vtkSmartPointer<vtkImageReader2> reader;
  if (starts_with(image.data, {0x89, 'P', 'N', 'G'}))
    reader = vtkSmartPointer<vtkPNGReader>::New();
  else if (starts_with(image.data, {0xFF, 0xD8, 0xFF}))
    reader = vtkSmartPointer<vtkJPEGReader>::New();
  else
    throw Error(ErrorCode::InvalidInput, what + ": not a PNG or JPEG image (" +
                                             (image.mime_type.empty() ? "no MIME type" : image.mime_type) +
                                             ")");
  bool failed = false;
  vtkNew<vtkCallbackCommand> on_error;
  on_error->SetCallback(note_error);
  on_error->SetClientData(&failed);
  reader->AddObserver(vtkCommand::ErrorEvent, on_error);
  reader->AddObserver(vtkCommand::WarningEvent, on_error);
  reader->SetMemoryBuffer(image.data.data());
  reader->SetMemoryBufferLength(static_cast<vtkIdType>(image.data.size()));
  // glTF puts v = 0 at the top row; the readers put the top row last, so flip it first.
  vtkNew<vtkImageFlip> flip;
  flip->SetFilteredAxis(1);
  flip->SetInputConnection(reader->GetOutputPort());
  flip->AddObserver(vtkCommand::ErrorEvent, on_error);
  flip->Update();
  vtkImageData* decoded = flip->GetOutput();
  int dims[3] = {0, 0, 0};
  decoded->GetDimensions(dims);
  if (failed || dims[0] <= 0 || dims[1] <= 0 || decoded->GetNumberOfScalarComponents() < 1)
    throw Error(ErrorCode::InvalidInput, what + ": the image data does not decode");
  vtkNew<vtkImageData> owned;
  owned->DeepCopy(decoded);
  auto texture = vtkSmartPointer<vtkTexture>::New();
  texture->SetInputData(owned);
  texture->InterpolateOn();
  texture->MipmapOn();
  texture->RepeatOn();
  texture->EdgeClampOff();
  texture->SetColorModeToDirectScalars();
  return texture;
}

}  // namespace deepcut
