#pragma once
// Cheap checks of an image file before it is decoded: its size read from the header (PNG,
// JPEG, BMP, PNM; other formats are decoded as they are) against the limits of
// doc/limits.md, and a truncated PNG or JPEG recognised by its missing end marker (a decoder
// would fill the missing rows with grey and return a plausible image).
#include <filesystem>
#include <string>

namespace mire::pipeline {

// Image limits (doc/limits.md).
constexpr long long kMaxImageSide = 16384;          // px, either side
constexpr long long kMaxImagePixels = 100'000'000;  // 100 megapixels

// True for the extensions mire reads as images (png, jpg, jpeg, bmp, tif, tiff, pgm, ppm,
// pnm, pbm, webp, jp2; any case). Other files in image folders are ignored.
bool isImageFile(const std::filesystem::path& path);

// Throws std::runtime_error naming the image when its header gives a size beyond the limits
// or it is truncated. Returns silently when the format is not one whose header is read here.
void checkImageFile(const std::filesystem::path& path);

}  // namespace mire::pipeline
