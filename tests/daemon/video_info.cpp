// SPDX-License-Identifier: MIT
// video_info FILE: "FRAMES WIDTH HEIGHT" of a video as OpenCV reads it back (frames counted).
#include <cstdio>

#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

int main(int argc, char **argv)
{
	if (argc != 2)
		return 2;
	cv::VideoCapture cap(argv[1]);
	if (!cap.isOpened()) {
		std::fprintf(stderr, "video_info: cannot open %s\n", argv[1]);
		return 1;
	}
	cv::Mat f;
	int n = 0, w = 0, h = 0;
	while (cap.read(f)) {
		n++;
		w = f.cols;
		h = f.rows;
	}
	std::printf("%d %d %d\n", n, w, h);
	return 0;
}
