// Writes the seeds of the igtl_message fuzz target into the folder given: a TRANSFORM, an
// 8-bit IMAGE and a STRING, packed by OpenIGTLink itself.
#include <igtlImageMessage.h>
#include <igtlStringMessage.h>
#include <igtlTransformMessage.h>

#include <filesystem>
#include <fstream>

#include "fuzz/seed_generator.hpp"

namespace {

bool write(const std::filesystem::path& path, ::igtl::MessageBase& message) {
  message.Pack();
  std::ofstream file(path, std::ios::binary);
  file.write(static_cast<const char*>(message.GetPackPointer()), message.GetPackSize());
  return static_cast<bool>(file);
}

}  // namespace

bool write_fuzz_seeds(const std::filesystem::path& folder) {
  ::igtl::TransformMessage::Pointer transform = ::igtl::TransformMessage::New();
  transform->SetDeviceName("ProbeToTracker");
  ::igtl::Matrix4x4 matrix;
  ::igtl::IdentityMatrix(matrix);
  matrix[0][3] = 12.5f;
  transform->SetMatrix(matrix);
  ::igtl::ImageMessage::Pointer image = ::igtl::ImageMessage::New();
  image->SetDeviceName("Image_Reference");
  image->SetDimensions(8, 6, 1);
  image->SetSpacing(0.2f, 0.25f, 1.0f);
  image->SetScalarType(::igtl::ImageMessage::TYPE_UINT8);
  image->AllocateScalars();
  auto* pixels = static_cast<unsigned char*>(image->GetScalarPointer());
  for (int i = 0; i < 48; ++i) pixels[i] = static_cast<unsigned char>(5 * i);
  ::igtl::StringMessage::Pointer text = ::igtl::StringMessage::New();
  text->SetDeviceName("Status");
  text->SetString("ok");
  return write(folder / "transform", *transform) && write(folder / "image", *image) && write(folder / "string", *text);
}
