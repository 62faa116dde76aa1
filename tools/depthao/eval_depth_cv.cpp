// SPDX-License-Identifier: MIT
// OpenCV's rgbd DepthCleaner for depthao-eval-cv (C++ only here: the rgbd module has no C
// API).  Method NIL (Nguyen, Izadi, Lovell 2012), window 5, on depth in metres.
#include <opencv2/rgbd.hpp>

extern "C" {
#include "eval_depth.h"
}

extern "C" int eval_cv_depth_clean(const float *in, int w, int h, float *out)
{
	try {
		static thread_local cv::Ptr<cv::rgbd::DepthCleaner> cleaner;
		if (!cleaner) {
			cv::setNumThreads(0);   // on this thread alone: its CPU time is the cleaner's
			cleaner = cv::rgbd::DepthCleaner::create(CV_32F, 5,
					cv::rgbd::DepthCleaner::DEPTH_CLEANER_NIL);
		}
		const cv::Mat src(h, w, CV_32F, const_cast<float *>(in));
		cv::Mat dst(h, w, CV_32F, out);
		cv::Mat res;
		(*cleaner)(src, res);
		if (res.rows != h || res.cols != w || res.type() != CV_32F)
			return -1;
		for (int y = 0; y < h; y++)
			for (int x = 0; x < w; x++) {
				const float z = res.at<float>(y, x);
				// no depth in, none out (the cleaner may leave NaN there)
				dst.at<float>(y, x) = in[(size_t)y * w + x] > 0.0f && z > 0.0f ? z : 0.0f;
			}
		return 0;
	} catch (const cv::Exception &) {
		return -1;
	}
}
