// The one reader of a list of image files, one frame per Read: the IR folders (folder:DIR, an
// image file) and the depth folders (depth:DIR) differ only in how an image read from disk becomes
// a frame, which each gives as a conversion.
#pragma once

#include "proxygrasp/sensing/frame_source.h"

#include <opencv2/core.hpp>

#include <functional>
#include <string>
#include <vector>

namespace pg {

class ImageListSource : public FrameSource {
 public:
  /// Turns an image as cv::imread(IMREAD_UNCHANGED) gave it (empty when the file is no readable
  /// image) into a frame; "" when it did, else why not (the file's name is put before it).
  using Convert = std::function<std::string(const cv::Mat& image, cv::Mat& frame)>;

  /// `description` is what Describe says; files are read in the order given.
  ImageListSource(std::string description, std::vector<std::string> files, Convert convert);

  /// The next file's frame; kError naming the file when it cannot be read or converted (the next
  /// Read goes on with the file after it), kEnd after the last.
  FrameStatus Read(cv::Mat& frame) override;
  std::string Describe() const override { return m_description; }

 private:
  std::string m_description;
  std::vector<std::string> m_files;
  Convert m_convert;
  size_t m_next = 0;
};

/// cv::imread(path, IMREAD_UNCHANGED), empty instead of an exception for a broken file.
cv::Mat ReadImageUnchanged(const std::string& path);

}  // namespace pg
