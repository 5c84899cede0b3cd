// SPDX-License-Identifier: MIT
#include "deepcut/widgets/texture.h"

#include <stb/stb_image.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <cstring>
#include <limits>
#include <memory>
#include <string>

#include "deepcut/core/errors.h"

namespace deepcut {
namespace {

/// Larger images are refused rather than decoded (a small file can claim a huge size).
constexpr long long kMaxPixels = 64ll * 1024 * 1024;

bool starts_with(const std::vector<unsigned char>& data, std::initializer_list<unsigned char> magic) {
  if (data.size() < magic.size()) return false;
  std::size_t i = 0;
  for (unsigned char m : magic)
    if (data[i++] != m) return false;
  return true;
}

}  // namespace

vtkSmartPointer<vtkTexture> make_texture(const Image& image) {
  const std::string what = "image '" + (image.name.empty() ? std::string("(unnamed)") : image.name) + "'";
  if (!starts_with(image.data, {0x89, 'P', 'N', 'G'}) && !starts_with(image.data, {0xFF, 0xD8, 0xFF}))
    throw Error(ErrorCode::InvalidInput, what + ": not a PNG or JPEG image (" +
                                             (image.mime_type.empty() ? "no MIME type" : image.mime_type) +
                                             ")");
  if (image.data.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw Error(ErrorCode::InvalidInput, what + ": too large");
  // stb_image reports failures as return values (never aborts or prints), unlike libpng
  // through VTK's readers.
  const auto size = static_cast<int>(image.data.size());
  int width = 0, height = 0, channels = 0;
  if (!stbi_info_from_memory(image.data.data(), size, &width, &height, &channels))
    throw Error(ErrorCode::InvalidInput,
                what + ": the image data does not decode (" + stbi_failure_reason() + ")");
  if (width <= 0 || height <= 0 || static_cast<long long>(width) * height > kMaxPixels)
    throw Error(ErrorCode::InvalidInput, what + ": " + std::to_string(width) + " x " +
                                             std::to_string(height) + " pixels is too large to show");
  std::unique_ptr<unsigned char, void (*)(void*)> pixels(
      stbi_load_from_memory(image.data.data(), size, &width, &height, &channels, 0), stbi_image_free);
  if (!pixels || channels < 1 || channels > 4)
    throw Error(ErrorCode::InvalidInput,
                what + ": the image data does not decode (" + stbi_failure_reason() + ")");

  // stb's first row is the top of the picture, where glTF puts v = 0; VTK's t = 0 is the first
  // row of the image data. So rows go over as they are and glTF UVs apply unchanged.
  vtkNew<vtkImageData> data;
  data->SetDimensions(width, height, 1);
  vtkNew<vtkUnsignedCharArray> scalars;
  scalars->SetNumberOfComponents(channels);
  scalars->SetNumberOfTuples(static_cast<vtkIdType>(width) * height);
  std::memcpy(scalars->GetPointer(0), pixels.get(), static_cast<std::size_t>(width) * height * channels);
  data->GetPointData()->SetScalars(scalars);
  auto texture = vtkSmartPointer<vtkTexture>::New();
  texture->SetInputData(data);
  texture->InterpolateOn();
  texture->MipmapOn();
  texture->RepeatOn();
  texture->EdgeClampOff();
  return texture;
}

}  // namespace deepcut
