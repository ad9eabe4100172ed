// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "unit/IoTestUtil.h"
#include "vdbmap/io/Image.h"

using namespace vdbmap;
using Catch::Matchers::Contains;

TEST_CASE("PNG round trip, colour and label images", "[io][image]") {
    test::TempDir dir;
    cv::Mat color(20, 30, CV_8UC3);
    cv::Mat labels(20, 30, CV_8UC1);
    for (int y = 0; y < 20; ++y) {
        for (int x = 0; x < 30; ++x) {
            color.at<cv::Vec3b>(y, x) = cv::Vec3b(x * 8, y * 12, (x + y) % 256);
            labels.at<std::uint8_t>(y, x) =
                static_cast<std::uint8_t>((x + y) % 22 == 21 ? 255 : (x + y) % 22);
        }
    }
    writePng(dir / "atlas" / "a.png", color);
    writePng(dir / "labels.png", labels);
    const cv::Mat color_back = readColorImage(dir / "atlas" / "a.png");
    const cv::Mat labels_back = readLabelImage(dir / "labels.png");
    CHECK(cv::norm(color_back, color, cv::NORM_INF) == 0);
    CHECK(cv::norm(labels_back, labels, cv::NORM_INF) == 0);
    CHECK(readImageSize(dir / "labels.png") == cv::Size(30, 20));
    CHECK(test::countEntries(dir / "atlas") == 1);

    // A colour image is not a label image.
    CHECK_THAT(test::ioErrorMessage([&] { readLabelImage(dir / "atlas" / "a.png"); }),
               Contains("a.png") && Contains("one channel") && Contains("3 channels"));
}

TEST_CASE("Unreadable or missing images throw IoError naming the file", "[io][image]") {
    test::TempDir dir;
    test::writeText(dir / "broken.png", "\x89PNG garbage");
    CHECK_THAT(test::ioErrorMessage([&] { readColorImage(dir / "broken.png"); }),
               Contains("broken.png"));
    CHECK_THAT(test::ioErrorMessage([&] { readColorImage(dir / "none.jpg"); }),
               Contains("none.jpg"));
    CHECK_THROWS_AS(writePng(dir / "empty.png", cv::Mat()), InvalidInput);
    CHECK_FALSE(std::filesystem::exists(dir / "empty.png"));
}
