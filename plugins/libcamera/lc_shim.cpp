// SPDX-License-Identifier: MIT
// Thin C++ shim over libcamera (0.0.3) for the libcamera depth source plugin.
#include "lc_shim.h"

#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <cstdlib>
#include <sys/mman.h>

#include <libcamera/libcamera.h>

using namespace libcamera;

static void set_err(char *err, size_t cap, const std::string &m)
{
	if (err && cap)
		std::snprintf(err, cap, "%s", m.c_str());
}

struct lcs_camera {
	std::unique_ptr<CameraManager> cm;
	std::shared_ptr<Camera> cam;
	std::unique_ptr<CameraConfiguration> config;
	std::unique_ptr<FrameBufferAllocator> alloc;
	std::vector<std::unique_ptr<Request>> requests;
	std::map<const FrameBuffer *, std::pair<void *, size_t>> maps;
	Stream *stream = nullptr;
	unsigned width = 0, height = 0, stride = 0, bits = 16;
	PixelFormat format;
	std::mutex lock;
	std::condition_variable ready;
	std::deque<Request *> done;
	Request *held = nullptr;   // handed to the caller, requeued on the next read
	std::vector<uint16_t> unpacked;
	bool started = false, gone = false, acquired = false;

	void on_complete(Request *r)
	{
		std::lock_guard<std::mutex> g(lock);
		done.push_back(r);
		ready.notify_one();
	}
	void on_removed()
	{
		std::lock_guard<std::mutex> g(lock);
		gone = true;
		ready.notify_one();
	}
};

static std::unique_ptr<CameraManager> start_manager(char *err, size_t cap)
{
	setenv("LIBCAMERA_LOG_LEVELS", "*:ERROR", 0); /* its chatter, unless the user asks */
	auto cm = std::make_unique<CameraManager>();
	int r = cm->start();
	if (r < 0) {
		set_err(err, cap, std::string("libcamera: cannot start the camera manager: ") + strerror(-r));
		return nullptr;
	}
	return cm;
}

extern "C" int lcs_list(void (*cb)(void *, const char *, const char *), void *user, char *err,
			size_t cap)
{
	auto cm = start_manager(err, cap);
	if (!cm)
		return -EIO;
	int n = 0;
	for (auto &cam : cm->cameras()) {
		std::string model = cam->id();
		const auto &props = cam->properties();
		if (auto m = props.get(properties::Model))
			model = *m;
		cb(user, cam->id().c_str(), model.c_str());
		n++;
	}
	cm->stop();
	return n;
}

extern "C" struct lcs_camera *lcs_open(const char *id, unsigned w, unsigned h, char *err, size_t cap)
{
	auto c = std::make_unique<lcs_camera>();
	if (!(c->cm = start_manager(err, cap)))
		return nullptr;
	auto cams = c->cm->cameras();
	if (cams.empty()) {
		set_err(err, cap, "libcamera: no cameras found");
		c->cm->stop();
		return nullptr;
	}
	c->cam = std::string(id) == "any" ? cams[0] : c->cm->get(id);
	if (!c->cam) {
		std::string ids;
		for (auto &k : cams)
			ids += (ids.empty() ? "" : ", ") + k->id();
		set_err(err, cap, std::string("libcamera: no camera '") + id + "' (cameras: " + ids + ")");
		c->cm->stop();
		return nullptr;
	}
	if (c->cam->acquire() < 0) {
		set_err(err, cap, "libcamera: the camera is in use by another program");
		c->cm->stop();
		return nullptr;
	}
	c->acquired = true;
	c->config = c->cam->generateConfiguration({StreamRole::Raw});
	if (!c->config || c->config->empty()) {
		set_err(err, cap, "libcamera: the camera has no raw stream");
		lcs_close(c.release());
		return nullptr;
	}
	StreamConfiguration &sc = c->config->at(0);
	const PixelFormat wanted[] = {formats::R12, formats::R10, formats::R8};
	bool found = false;
	for (const PixelFormat &f : wanted) {
		for (const PixelFormat &have : sc.formats().pixelformats())
			if (have == f) {
				sc.pixelFormat = f;
				found = true;
				break;
			}
		if (found)
			break;
	}
	if (!found) {
		set_err(err, cap, "libcamera: the camera offers no mono raw format (R12, R10 or R8) "
				  "for depth");
		lcs_close(c.release());
		return nullptr;
	}
	if (w && h)
		sc.size = Size(w, h);
	sc.bufferCount = 4;
	if (c->config->validate() == CameraConfiguration::Invalid ||
	    c->cam->configure(c->config.get()) < 0) {
		set_err(err, cap, "libcamera: the camera refused the configuration " + sc.toString());
		lcs_close(c.release());
		return nullptr;
	}
	c->stream = sc.stream();
	c->format = sc.pixelFormat;
	c->width = sc.size.width;
	c->height = sc.size.height;
	c->stride = sc.stride;
	c->bits = sc.pixelFormat == formats::R8 ? 8 : sc.pixelFormat == formats::R10 ? 10 : 12;
	c->alloc = std::make_unique<FrameBufferAllocator>(c->cam);
	if (c->alloc->allocate(c->stream) < 0) {
		set_err(err, cap, "libcamera: cannot allocate buffers");
		lcs_close(c.release());
		return nullptr;
	}
	for (const auto &buf : c->alloc->buffers(c->stream)) {
		const FrameBuffer::Plane &p = buf->planes()[0];
		void *m = mmap(nullptr, p.offset + p.length, PROT_READ, MAP_SHARED, p.fd.get(), 0);
		if (m == MAP_FAILED) {
			set_err(err, cap, "libcamera: cannot map a buffer");
			lcs_close(c.release());
			return nullptr;
		}
		c->maps[buf.get()] = {m, p.offset + p.length};
		auto req = c->cam->createRequest();
		if (!req || req->addBuffer(c->stream, buf.get()) < 0) {
			set_err(err, cap, "libcamera: cannot create a request");
			lcs_close(c.release());
			return nullptr;
		}
		c->requests.push_back(std::move(req));
	}
	c->cam->requestCompleted.connect(c.get(), &lcs_camera::on_complete);
	c->cam->disconnected.connect(c.get(), &lcs_camera::on_removed);
	c->unpacked.resize((size_t)c->width * c->height);
	return c.release();
}

extern "C" void lcs_describe(const struct lcs_camera *c, unsigned *w, unsigned *h, unsigned *bits,
			     char *text, size_t cap)
{
	*w = c->width;
	*h = c->height;
	*bits = c->bits;
	std::snprintf(text, cap, "libcamera %s: %s %ux%u", c->cam->id().c_str(),
		      c->format.toString().c_str(), c->width, c->height);
}

extern "C" int lcs_start(struct lcs_camera *c, char *err, size_t cap)
{
	if (c->cam->start() < 0) {
		set_err(err, cap, "libcamera: cannot start the camera");
		return -EIO;
	}
	c->started = true;
	for (auto &r : c->requests)
		if (c->cam->queueRequest(r.get()) < 0) {
			set_err(err, cap, "libcamera: cannot queue a request");
			return -EIO;
		}
	return 0;
}

extern "C" int lcs_read(struct lcs_camera *c, int timeout_ms, const uint16_t **data,
			unsigned *stride_bytes, uint64_t *timestamp_ns, uint64_t *sequence)
{
	if (c->held) { // the previous frame goes back to the camera
		c->held->reuse(Request::ReuseBuffers);
		c->cam->queueRequest(c->held);
		c->held = nullptr;
	}
	std::unique_lock<std::mutex> g(c->lock);
	for (;;) {
		if (c->gone)
			return -ENODEV;
		if (!c->ready.wait_for(g, std::chrono::milliseconds(timeout_ms < 0 ? 1000000 : timeout_ms),
				       [c] { return c->gone || !c->done.empty(); }))
			return -EAGAIN;
		if (c->gone)
			return -ENODEV;
		Request *r = c->done.front();
		c->done.pop_front();
		if (r->status() != Request::RequestComplete) {
			g.unlock();
			r->reuse(Request::ReuseBuffers);
			c->cam->queueRequest(r);
			g.lock();
			continue;
		}
		FrameBuffer *buf = r->buffers().begin()->second;
		const auto &md = buf->metadata();
		const uint8_t *src = (const uint8_t *)c->maps[buf].first + buf->planes()[0].offset;
		for (unsigned y = 0; y < c->height; y++) {
			const uint8_t *row = src + (size_t)y * c->stride;
			uint16_t *out = &c->unpacked[(size_t)y * c->width];
			for (unsigned x = 0; x < c->width; x++)
				out[x] = c->bits == 8 ? row[x] : (uint16_t)(row[2 * x] | (row[2 * x + 1] << 8));
		}
		*data = c->unpacked.data();
		*stride_bytes = c->width * 2;
		*timestamp_ns = md.timestamp;
		*sequence = md.sequence;
		c->held = r;
		return 0;
	}
}

extern "C" void lcs_close(struct lcs_camera *c)
{
	if (!c)
		return;
	if (c->started)
		c->cam->stop();
	c->requests.clear();
	for (auto &m : c->maps)
		munmap(m.second.first, m.second.second);
	c->alloc.reset();
	if (c->acquired)
		c->cam->release();
	c->cam.reset();
	if (c->cm)
		c->cm->stop();
	delete c;
}
