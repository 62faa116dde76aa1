// SPDX-License-Identifier: MIT
// Thin C++ shim over OpenCV's VideoWriter and highgui for the opencv sink plugin.
#include "cv_shim.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/highgui.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <opencv2/videoio/registry.hpp>

struct cvs_video {
	cv::VideoWriter writer;
	int width, height, color;
	cv::Mat bgr;
};

static void set_err(char *err, size_t cap, const std::string &msg)
{
	if (err && cap)
		std::snprintf(err, cap, "%s", msg.c_str());
}

extern "C" void cvs_video_backends(char *out, size_t cap)
{
	std::string s;
	try {
		for (auto b : cv::videoio_registry::getWriterBackends())
			s += (s.empty() ? "" : ", ") + cv::videoio_registry::getBackendName(b);
	} catch (...) {
	}
	std::snprintf(out, cap, "%s", s.empty() ? "none" : s.c_str());
}

extern "C" struct cvs_video *cvs_video_open(const char *path, const char fourcc[4], double fps,
					    int width, int height, int color, char *err,
					    size_t cap)
{
	try {
		auto *v = new cvs_video;
		v->width = width;
		v->height = height;
		v->color = color;
		int cc = cv::VideoWriter::fourcc(fourcc[0], fourcc[1], fourcc[2], fourcc[3]);
		if (!v->writer.open(path, cc, fps, cv::Size(width, height), color != 0)) {
			char backends[256];
			cvs_video_backends(backends, sizeof backends);
			set_err(err, cap, std::string("this OpenCV cannot write ") +
						  std::string(fourcc, 4) + " to " + path +
						  " (writer backends: " + backends +
						  "; MJPG in .avi always works)");
			delete v;
			return nullptr;
		}
		return v;
	} catch (const cv::Exception &e) {
		set_err(err, cap, std::string("OpenCV: ") + e.what());
		return nullptr;
	}
}

extern "C" int cvs_video_write(struct cvs_video *v, const uint8_t *data, int stride, char *err,
			       size_t cap)
{
	try {
		cv::Mat in(v->height, v->width, v->color ? CV_8UC3 : CV_8UC1,
			   const_cast<uint8_t *>(data), (size_t)stride);
		if (v->color) {
			cv::cvtColor(in, v->bgr, cv::COLOR_RGB2BGR);
			v->writer.write(v->bgr);
		} else {
			v->writer.write(in);
		}
		return 0;
	} catch (const cv::Exception &e) {
		set_err(err, cap, std::string("OpenCV: ") + e.what());
		return -1;
	}
}

extern "C" void cvs_video_close(struct cvs_video *v)
{
	if (!v)
		return;
	try {
		v->writer.release();
	} catch (...) {
	}
	delete v;
}

struct cvs_window {
	std::string title;
	std::vector<cvs_control> controls;
	std::vector<int> positions;
	cv::Mat bgr;
};

extern "C" struct cvs_window *cvs_window_open(const char *title, struct cvs_control *controls,
					      int ncontrols, char *err, size_t cap)
{
	try {
		auto *w = new cvs_window;
		w->title = title;
		w->controls.assign(controls, controls + ncontrols);
		cv::namedWindow(w->title, cv::WINDOW_AUTOSIZE);
		for (auto &c : w->controls) {
			int max = (int)std::lround((c.max - c.min) / c.step);
			int pos = (int)std::lround((c.value - c.min) / c.step);
			w->positions.push_back(pos < 0 ? 0 : pos > max ? max : pos);
			cv::createTrackbar(c.name, w->title, nullptr, max);
			cv::setTrackbarPos(c.name, w->title, w->positions.back());
		}
		return w;
	} catch (const cv::Exception &e) {
		set_err(err, cap, std::string("OpenCV window: ") + e.what());
		return nullptr;
	}
}

extern "C" int cvs_window_show(struct cvs_window *w, const uint8_t *data, int width, int height,
			       int stride, int channels, const char *overlay)
{
	try {
		cv::Mat in(height, width, channels == 3 ? CV_8UC3 : CV_8UC1,
			   const_cast<uint8_t *>(data), (size_t)stride);
		if (channels == 3)
			cv::cvtColor(in, w->bgr, cv::COLOR_RGB2BGR);
		else
			cv::cvtColor(in, w->bgr, cv::COLOR_GRAY2BGR);
		if (overlay && *overlay) {
			cv::putText(w->bgr, overlay, cv::Point(8, 22), cv::FONT_HERSHEY_SIMPLEX, 0.6,
				    cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
			cv::putText(w->bgr, overlay, cv::Point(8, 22), cv::FONT_HERSHEY_SIMPLEX, 0.6,
				    cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
		}
		cv::imshow(w->title, w->bgr);
		cv::waitKey(1);
		if (cv::getWindowProperty(w->title, cv::WND_PROP_VISIBLE) < 1)
			return -1;
		int moved = 0;
		for (size_t i = 0; i < w->controls.size(); i++) {
			int pos = cv::getTrackbarPos(w->controls[i].name, w->title);
			if (pos != w->positions[i]) {
				w->positions[i] = pos;
				w->controls[i].value = w->controls[i].min + pos * w->controls[i].step;
				moved |= 1 << i;
			}
		}
		return moved;
	} catch (const cv::Exception &) {
		return -1;
	}
}

extern "C" void cvs_window_close(struct cvs_window *w)
{
	if (!w)
		return;
	try {
		cv::destroyWindow(w->title);
		cv::waitKey(1);
	} catch (...) {
	}
	delete w;
}
