// SPDX-License-Identifier: MIT
//
// depthao_node: the ROS 1 shell around ros/common/dao_ros.c (all logic is
// there, in C on the public API, for a ROS 2 node to reuse).  ROS 1 has no C
// API, so this file only moves message fields into dao_ros structs and back,
// reads the private parameters at start, and serves dynamic_reconfigure's
// protocol (descriptions, updates, set_parameters) from depthao's parameter
// table, without its code generator.
//
//   in:  depth/image (16UC1, mono16, 32FC1) + depth/camera_info (image_transport)
//   out: ao/image (mono16 or 32FC1), shaded/image (rgb8), the input's header;
//        depth_filtered/image (16UC1 in the input's unit, or 32FC1) with
//        depth_filtered/camera_info, and depth_filtered/image/compressedDepth
//        (image_transport's compressedDepth format, PNG or RVL), each computed
//        only while it has subscribers.  Plain publishers, not image_transport's:
//        an installed compressed_depth plugin would advertise the same topic.
//   poses: with ~pose_frame, each image's frame in that fixed frame from tf at
//        the image's stamp (tf2_ros), for depth_temporal_motion source and
//        source+icp: the temporal filters follow the camera's motion.
//   out: camera_pose (geometry_msgs/PoseStamped): where the motion is followed,
//        the camera's pose in ~odom_frame (the first followed frame's optical
//        frame), as depthao process --pose-out gives it.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <dynamic_reconfigure/Config.h>
#include <dynamic_reconfigure/ConfigDescription.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <geometry_msgs/PoseStamped.h>
#include <image_transport/image_transport.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <tf2/exceptions.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "dao_ros.h"
#include "dao_ros_cdepth.h"

namespace {

// Sets one AO parameter from a ROS parameter value of any type.
int set_from_xmlrpc(dao_params *p, const dao_param_info *pi, XmlRpc::XmlRpcValue &v,
		    dao_error *err)
{
	switch (v.getType()) {
	case XmlRpc::XmlRpcValue::TypeDouble:
		return dao_ros_param_set_double(p, pi, static_cast<double>(v), err);
	case XmlRpc::XmlRpcValue::TypeInt:
		return dao_ros_param_set_int(p, pi, static_cast<int>(v), err);
	case XmlRpc::XmlRpcValue::TypeString:
		return dao_ros_param_set_string(p, pi, static_cast<std::string>(v).c_str(), err);
	default:
		std::snprintf(err->message, sizeof err->message,
			      "%s: give a number or a name, not a %s", pi->name,
			      v.getType() == XmlRpc::XmlRpcValue::TypeBoolean ? "boolean" : "list or map");
		return err->code = -EINVAL;
	}
}

std::string text_of(XmlRpc::XmlRpcValue &v)
{
	switch (v.getType()) {
	case XmlRpc::XmlRpcValue::TypeDouble: {
		char b[64];
		std::snprintf(b, sizeof b, "%.17g", static_cast<double>(v));
		return b;
	}
	case XmlRpc::XmlRpcValue::TypeInt:
		return std::to_string(static_cast<int>(v));
	case XmlRpc::XmlRpcValue::TypeString:
		return static_cast<std::string>(v);
	default:
		return "";
	}
}

class DepthaoNode {
public:
	DepthaoNode() : pnh_("~"), it_(nh_) { dao_ros_cdepth_init(&cdepth_); }
	~DepthaoNode()
	{
		dao_ros_proc_destroy(proc_);
		dao_ros_cdepth_free(&cdepth_);
	}

	bool start();

private:
	void on_depth(const sensor_msgs::ImageConstPtr &img, const sensor_msgs::CameraInfoConstPtr &info);
	bool on_set(dynamic_reconfigure::Reconfigure::Request &req,
		    dynamic_reconfigure::Reconfigure::Response &res);
	bool read_parameters(dao_ros_settings *s, dao_params *p);
	bool read_cdepth_parameters();
	bool read_pose_parameters();
	void check_pose_use(const dao_params &p);
	void set_pose(const std_msgs::Header &h);
	bool wait_for_transform(const std::string &frame, const ros::Time &stamp, std::string *why);
	void publish_depth(const sensor_msgs::ImageConstPtr &img,
			   const sensor_msgs::CameraInfoConstPtr &info);
	dynamic_reconfigure::Config config_of(const dao_params &p, int which) const;
	void publish_config(const dao_params &p);
	void log_error(const char *what, const dao_error &err);

	ros::NodeHandle nh_, pnh_;
	image_transport::ImageTransport it_;
	image_transport::CameraSubscriber sub_;
	image_transport::Publisher ao_pub_, shaded_pub_;
	ros::Publisher descr_pub_, update_pub_;
	ros::ServiceServer set_srv_;
	dao_ros_proc *proc_ = nullptr;
	std::vector<dao_ros_param_desc> descs_;
	dao_params defaults_{};
	sensor_msgs::Image ao_msg_, shaded_msg_;  // reused: their data keep their capacity
	ros::Publisher depth_pub_, depth_info_pub_, cdepth_pub_, pose_pub_;
	std::string odom_frame_ = "depthao_odom";
	geometry_msgs::PoseStamped pose_msg_;
	sensor_msgs::Image depth_msg_;
	sensor_msgs::CameraInfo depth_info_msg_;
	sensor_msgs::CompressedImage cdepth_msg_;
	dao_ros_cdepth cdepth_;
	bool warned_distortion_ = false;
	// poses from tf (~pose_frame): looked up only while the motion mode uses them
	std::string pose_frame_;
	double pose_timeout_ = 0.1;
	std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
	std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
	bool poses_used_ = false, said_pose_ok_ = false;
	int checked_motion_ = -1;  // the motion mode check_pose_use() last saw
	bool have_pose_stamp_ = false;
	uint64_t last_pose_stamp_ = 0;
	std::string last_error_;
	ros::WallTime last_error_time_;
};

// The same error is logged again after 10 s, another one at once.
void DepthaoNode::log_error(const char *what, const dao_error &err)
{
	ros::WallTime now = ros::WallTime::now();
	if (last_error_ == err.message && (now - last_error_time_).toSec() < 10.0)
		return;
	last_error_ = err.message;
	last_error_time_ = now;
	ROS_ERROR("%s: %s", what, err.message);
}

bool DepthaoNode::read_parameters(dao_ros_settings *s, dao_params *p)
{
	dao_error err{};
	dao_ros_settings_init(s);
	std::string quality = "default";
	pnh_.param<std::string>("quality", quality, "default");
	dao_quality q;
	if (dao_quality_parse(quality.c_str(), &q, &err)) {
		ROS_FATAL("~quality: %s", err.message);
		return false;
	}
	dao_params_init(p, q);
	bool stream = true;
	pnh_.param("stream", stream, true);
	if (stream)
		dao_params_stream_defaults(p);
	defaults_ = *p;

	const char *settings[] = { "depth_unit", "ao_encoding" };
	for (const char *name : settings) {
		XmlRpc::XmlRpcValue v;
		if (pnh_.getParam(name, v) && dao_ros_settings_set(s, name, text_of(v).c_str(), &err)) {
			ROS_FATAL("~%s", err.message);
			return false;
		}
	}
	size_t count;
	const dao_param_info *table = dao_param_table(&count);
	for (size_t i = 0; i < count; i++) {
		dao_ros_param_desc d;
		dao_ros_param_describe(&table[i], &d);
		descs_.push_back(d);
		XmlRpc::XmlRpcValue v;
		if (pnh_.getParam(d.name, v) && set_from_xmlrpc(p, d.info, v, &err)) {
			ROS_FATAL("~%s (%s): %s", d.name, d.info->help, err.message);
			return false;
		}
	}
	// a misspelt private parameter would otherwise be ignored silently
	std::vector<std::string> names;
	const std::string ns = pnh_.getNamespace() + "/";
	if (ros::param::getParamNames(names))
		for (const std::string &full : names) {
			if (full.compare(0, ns.size(), ns) != 0)
				continue;
			std::string n = full.substr(ns.size());
			if (n == "quality" || n == "stream" || n == "depth_unit" || n == "ao_encoding" ||
			    n == "queue_size" || n == "pose_frame" || n == "pose_timeout" ||
			    n == "odom_frame" ||
			    n.find('/') != std::string::npos ||
			    dao_param_find(n.c_str()))
				continue;
			ROS_WARN("~%s is not a parameter of depthao_node: ignored (the AO parameters "
				 "are those of depthao process --help, with '_' for '-')", n.c_str());
		}
	return true;
}

// compressed_depth_image_transport's parameters, where its publisher reads them:
// IMAGE_TOPIC/compressedDepth/{format, png_level, depth_max, depth_quantization}
bool DepthaoNode::read_cdepth_parameters()
{
	const char *names[] = { "format", "png_level", "depth_max", "depth_quantization" };
	for (const char *name : names) {
		XmlRpc::XmlRpcValue v;
		const std::string key = "depth_filtered/image/compressedDepth/" + std::string(name);
		dao_error err{};
		if (nh_.getParam(key, v) && dao_ros_cdepth_set(&cdepth_, name, text_of(v).c_str(), &err)) {
			ROS_FATAL("%s: %s", nh_.resolveName(key).c_str(), err.message);
			return false;
		}
	}
	return true;
}

// Frames in tf2 have no leading '/' (tf2_ros strips it from what it receives);
// older drivers still send one.
std::string tf2_frame(const std::string &f)
{
	return !f.empty() && f[0] == '/' ? f.substr(1) : f;
}

bool DepthaoNode::read_pose_parameters()
{
	XmlRpc::XmlRpcValue v;
	if (pnh_.getParam("pose_frame", v)) {
		if (v.getType() != XmlRpc::XmlRpcValue::TypeString) {
			ROS_FATAL("~pose_frame: give tf's fixed frame as a name (odom, map), not a %s",
				  v.getType() == XmlRpc::XmlRpcValue::TypeBoolean ? "boolean" : "number");
			return false;
		}
		const std::string given = static_cast<std::string>(v);
		pose_frame_ = tf2_frame(given);
		if (!given.empty() && pose_frame_.empty()) {
			ROS_FATAL("~pose_frame '%s' names no frame: give tf's fixed frame (odom, map)",
				  given.c_str());
			return false;
		}
	}
	if (pnh_.getParam("pose_timeout", v)) {
		if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble)
			pose_timeout_ = static_cast<double>(v);
		else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
			pose_timeout_ = static_cast<int>(v);
		else
			pose_timeout_ = -1.0; /* refused below */
	}
	if (!std::isfinite(pose_timeout_) || pose_timeout_ < 0.0 || pose_timeout_ > 10.0) {
		ROS_FATAL("~pose_timeout: %s is not a wait for tf in seconds (0 to 10; 0.1 by default)",
			  text_of(v).empty() ? "that" : text_of(v).c_str());
		return false;
	}
	if (pnh_.getParam("odom_frame", v)) {
		if (v.getType() != XmlRpc::XmlRpcValue::TypeString ||
		    tf2_frame(static_cast<std::string>(v)).empty()) {
			ROS_FATAL("~odom_frame: give the name of the frame camera_pose is in "
				  "(depthao_odom by default)");
			return false;
		}
		odom_frame_ = tf2_frame(static_cast<std::string>(v));
	}
	if (odom_frame_ == pose_frame_) {
		ROS_FATAL("~odom_frame '%s' is ~pose_frame: camera_pose is in a frame of its own "
			  "(the first followed frame's optical frame), not in tf's fixed frame; give "
			  "~odom_frame another name (depthao_odom by default)",
			  odom_frame_.c_str());
		return false;
	}
	if (!pose_frame_.empty()) {
		tf_buffer_.reset(new tf2_ros::Buffer());
		tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_, nh_));
	}
	return true;
}

// Says when the poses and the motion mode do not go together: at start, and
// when a reconfigure changes the mode.
void DepthaoNode::check_pose_use(const dao_params &p)
{
	if (p.depth_temporal_motion == checked_motion_)
		return;
	checked_motion_ = p.depth_temporal_motion;
	const bool wants = p.depth_temporal_motion == DAO_DEPTH_MOTION_SOURCE ||
			   p.depth_temporal_motion == DAO_DEPTH_MOTION_SOURCE_ICP;
	poses_used_ = wants && !pose_frame_.empty();
	if (wants && pose_frame_.empty())
		ROS_WARN("depth_temporal_motion is %s but ~pose_frame is not set: no frame has a "
			 "pose, so %s; set ~pose_frame to tf's fixed frame (odom, map, world)",
			 p.depth_temporal_motion == DAO_DEPTH_MOTION_SOURCE ? "source" : "source+icp",
			 p.depth_temporal_motion == DAO_DEPTH_MOTION_SOURCE
				 ? "the history stays where it was, as with off (a still camera)"
				 : "the motion is estimated from the depth alone, as with icp");
	else if (!wants && !pose_frame_.empty())
		ROS_WARN("~pose_frame '%s' is set but depth_temporal_motion is not source or "
			 "source+icp: the poses are not used (no tf lookups)", pose_frame_.c_str());
}

// Whether tf can place `frame` in ~pose_frame at `stamp` within ~pose_timeout
// of wall-clock time (tf2_ros' own wait counts ROS time, which stands still
// under sim time without /clock).
bool DepthaoNode::wait_for_transform(const std::string &frame, const ros::Time &stamp,
				     std::string *why)
{
	const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(pose_timeout_);
	for (;;) {
		why->clear();
		if (tf_buffer_->canTransform(pose_frame_, frame, stamp, ros::Duration(0), why))
			return true;
		if (ros::WallTime::now() >= deadline || !ros::ok())
			return false;
		ros::WallDuration(0.002).sleep();
	}
}

// The image's frame in ~pose_frame at the image's stamp, for the next run; no
// pose (the motion mode's fallback for this frame and the next) when tf cannot
// give it in ~pose_timeout.
void DepthaoNode::set_pose(const std_msgs::Header &h)
{
	dao_error err{};
	const uint64_t stamp = dao_ros_stamp_ns(h.stamp.sec, h.stamp.nsec);
	const std::string frame = tf2_frame(h.frame_id);
	std::string why;
	// a bag played again without sim time: tf keeps the first play's transforms
	// (10 s of them) and refuses older ones; start it over with the histories
	// (static transforms stay)
	if (have_pose_stamp_ && stamp < last_pose_stamp_)
		tf_buffer_->clear();
	have_pose_stamp_ = true;
	last_pose_stamp_ = stamp;
	if (frame.empty())
		why = "the depth image has no frame_id";
	else if (wait_for_transform(frame, h.stamp, &why)) {
		try {
			const geometry_msgs::Transform t =
				tf_buffer_->lookupTransform(pose_frame_, frame, h.stamp).transform;
			const double q[4] = { t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w };
			const double v[3] = { t.translation.x, t.translation.y, t.translation.z };
			if (dao_ros_proc_set_pose(proc_, stamp, q, v, &err) == 0) {
				if (!said_pose_ok_)
					ROS_INFO("poses: '%s' in '%s' from tf at each image's stamp",
						 frame.c_str(), pose_frame_.c_str());
				said_pose_ok_ = true;
				return;
			}
			why = std::string("tf gave no pose: ") + err.message;
		} catch (const tf2::TransformException &e) {
			why = e.what();
		}
	} else if (why.empty())
		why = "tf has no transform in time (~pose_timeout " + std::to_string(pose_timeout_) + " s)";
	ROS_WARN_THROTTLE(5.0, "no pose for the depth image of %u.%09u s: '%s' in '%s': %s; "
			  "this frame and the next go without the camera's motion (source: the "
			  "history stays where it was; source+icp: ICP alone)",
			  h.stamp.sec, h.stamp.nsec, frame.c_str(), pose_frame_.c_str(), why.c_str());
	if (dao_ros_proc_set_pose(proc_, stamp, nullptr, nullptr, &err))
		log_error("pose", err);
}

dynamic_reconfigure::Config DepthaoNode::config_of(const dao_params &p, int which) const
{
	// which: 0 the values of p, -1 the minima, 1 the maxima
	dynamic_reconfigure::Config c;
	for (const dao_ros_param_desc &d : descs_) {
		switch (d.kind) {
		case DAO_ROS_PARAM_DOUBLE: {
			dynamic_reconfigure::DoubleParameter v;
			v.name = d.name;
			v.value = which < 0 ? d.min : which > 0 ? d.max : dao_ros_param_get_double(&p, d.info);
			c.doubles.push_back(v);
			break;
		}
		case DAO_ROS_PARAM_INT: {
			dynamic_reconfigure::IntParameter v;
			v.name = d.name;
			v.value = which < 0 ? static_cast<int>(d.min) : which > 0 ? static_cast<int>(d.max)
					: static_cast<int>(dao_ros_param_get_int(&p, d.info));
			c.ints.push_back(v);
			break;
		}
		case DAO_ROS_PARAM_STRING: {
			dynamic_reconfigure::StrParameter v;
			v.name = d.name;
			char buf[64] = "";
			if (which == 0)
				dao_ros_param_get_string(&p, d.info, buf, sizeof buf, nullptr);
			v.value = buf;
			c.strs.push_back(v);
			break;
		}
		}
	}
	dynamic_reconfigure::GroupState g;
	g.name = "Default";
	g.state = true;
	g.id = 0;
	g.parent = 0;
	c.groups.push_back(g);
	return c;
}

// The enums as dynamic_reconfigure's edit_method (a Python literal rqt_reconfigure
// and the Python client evaluate), so they take names: {"prefilter": "domain"}.
std::string edit_method(const dao_param_info *pi)
{
	if (pi->type != DAO_PARAM_ENUM)
		return "";
	std::string s = "{'enum_description': '" + std::string(pi->name) + "', 'enum': [";
	for (int i = 0; pi->enum_names[i]; i++)
		s += std::string(i ? ", " : "") + "{'name': '" + pi->enum_names[i] +
		     "', 'type': 'int', 'value': " + std::to_string(i) +
		     ", 'description': '', 'srcline': 0, 'srcfile': '', 'cconsttype': 'const int', "
		     "'ctype': 'int'}";
	return s + "]}";
}

void DepthaoNode::publish_config(const dao_params &p)
{
	update_pub_.publish(config_of(p, 0));
	// the parameter server shows the values in use, as dynamic_reconfigure's server does
	for (const dao_ros_param_desc &d : descs_) {
		if (d.kind == DAO_ROS_PARAM_DOUBLE)
			pnh_.setParam(d.name, dao_ros_param_get_double(&p, d.info));
		else if (d.kind == DAO_ROS_PARAM_INT)
			pnh_.setParam(d.name, static_cast<int>(dao_ros_param_get_int(&p, d.info)));
		else {
			char buf[64];
			if (!dao_ros_param_get_string(&p, d.info, buf, sizeof buf, nullptr))
				pnh_.setParam(d.name, std::string(buf));
		}
	}
}

bool DepthaoNode::start()
{
	dao_ros_settings s;
	dao_params p;
	if (!read_parameters(&s, &p) || !read_pose_parameters())
		return false;
	dao_error err{};
	if (dao_ros_proc_create(&proc_, &s, &p, &err)) {
		ROS_FATAL("%s", err.message);
		return false;
	}
	int queue = 5;
	pnh_.param("queue_size", queue, 5);
	if (queue < 1) {
		ROS_FATAL("~queue_size: %d is not a queue length (1 or more)", queue);
		return false;
	}
	ao_pub_ = it_.advertise("ao/image", queue);
	shaded_pub_ = it_.advertise("shaded/image", queue);
	if (!read_cdepth_parameters())
		return false;
	depth_pub_ = nh_.advertise<sensor_msgs::Image>("depth_filtered/image", queue);
	depth_info_pub_ = nh_.advertise<sensor_msgs::CameraInfo>("depth_filtered/camera_info", queue);
	cdepth_pub_ = nh_.advertise<sensor_msgs::CompressedImage>("depth_filtered/image/compressedDepth",
								   queue);
	pose_pub_ = nh_.advertise<geometry_msgs::PoseStamped>("camera_pose", queue);

	dynamic_reconfigure::ConfigDescription descr;
	dynamic_reconfigure::Group g;
	g.name = "Default";
	g.type = "";
	g.id = 0;
	g.parent = 0;
	for (const dao_ros_param_desc &d : descs_) {
		dynamic_reconfigure::ParamDescription pd;
		pd.name = d.name;
		pd.type = d.kind == DAO_ROS_PARAM_DOUBLE ? "double" : d.kind == DAO_ROS_PARAM_INT ? "int" : "str";
		pd.level = 0;
		pd.description = d.info->help;
		if (d.info->unit)
			pd.description += std::string(" (") + d.info->unit + ")";
		pd.edit_method = edit_method(d.info);
		g.parameters.push_back(pd);
	}
	descr.groups.push_back(g);
	descr.min = config_of(p, -1);
	descr.max = config_of(p, 1);
	descr.dflt = config_of(defaults_, 0);
	descr_pub_ = pnh_.advertise<dynamic_reconfigure::ConfigDescription>("parameter_descriptions", 1, true);
	update_pub_ = pnh_.advertise<dynamic_reconfigure::Config>("parameter_updates", 1, true);
	descr_pub_.publish(descr);
	publish_config(p);
	check_pose_use(p);
	set_srv_ = pnh_.advertiseService("set_parameters", &DepthaoNode::on_set, this);

	sub_ = it_.subscribeCamera("depth/image", queue, &DepthaoNode::on_depth, this);
	ROS_INFO("depthao %s: %s + %s -> %s (%s), %s (rgb8); depth_unit %g m%s%s", dao_version(),
		 sub_.getTopic().c_str(), sub_.getInfoTopic().c_str(), ao_pub_.getTopic().c_str(),
		 dao_ros_ao_encoding_name(s.ao_encoding), shaded_pub_.getTopic().c_str(),
		 static_cast<double>(s.depth_unit), pose_frame_.empty() ? "" : "; poses in ",
		 pose_frame_.c_str());
	return true;
}

bool DepthaoNode::on_set(dynamic_reconfigure::Reconfigure::Request &req,
			 dynamic_reconfigure::Reconfigure::Response &res)
{
	dao_params p;
	dao_ros_proc_get_params(proc_, &p);
	dao_error err{};
	auto apply = [&](const std::string &name, auto set) {
		const dao_param_info *pi = dao_param_find(name.c_str());
		if (!pi)
			ROS_ERROR("set_parameters: '%s' is not an AO parameter", name.c_str());
		else if (set(pi))
			ROS_ERROR("set_parameters: %s; %s keeps its value", err.message, name.c_str());
	};
	for (const auto &v : req.config.doubles)
		apply(v.name, [&](const dao_param_info *pi) { return dao_ros_param_set_double(&p, pi, v.value, &err); });
	for (const auto &v : req.config.ints)
		apply(v.name, [&](const dao_param_info *pi) { return dao_ros_param_set_int(&p, pi, v.value, &err); });
	for (const auto &v : req.config.strs)
		apply(v.name, [&](const dao_param_info *pi) { return dao_ros_param_set_string(&p, pi, v.value.c_str(), &err); });
	for (const auto &v : req.config.bools)
		ROS_ERROR("set_parameters: %s: depthao has no boolean parameters", v.name.c_str());
	if (dao_ros_proc_set_params(proc_, &p, &err))
		ROS_ERROR("set_parameters: %s (nothing changed)", err.message);
	dao_ros_proc_get_params(proc_, &p);
	res.config = config_of(p, 0);
	publish_config(p);
	check_pose_use(p);
	return true;
}

void DepthaoNode::on_depth(const sensor_msgs::ImageConstPtr &img,
			   const sensor_msgs::CameraInfoConstPtr &info)
{
	const dao_ros_image depth = { img->width, img->height, img->encoding.c_str(), img->is_bigendian,
				      img->step, img->data.data(), img->data.size() };
	const dao_ros_camera_info ci = { info->width, info->height, info->K.data(), info->D.data(),
					 info->D.size(), info->P.data() };
	dao_ros_output ao, shaded;
	int distorted;
	dao_error err{};
	if (dao_ros_proc_prepare(proc_, &depth, &ci, &ao, &shaded, &distorted, &err)) {
		log_error(sub_.getTopic().c_str(), err);
		return;
	}
	if (distorted && !warned_distortion_) {
		ROS_WARN("%s: the camera info has distortion coefficients: depthao does not undistort, "
			 "the depth must be rectified (image_rect; it is used as it is); intrinsics %s",
			 sub_.getInfoTopic().c_str(),
			 distorted == DAO_ROS_DISTORTED_P ? "from P, the rectified image's"
							  : "from K (the camera info has no usable P)");
		warned_distortion_ = true;
	}
	// the messages are kept: once sized, resize() and the header's copy reuse their memory
	const bool want_shaded = shaded_pub_.getNumSubscribers() > 0;
	sensor_msgs::Image *msgs[2] = { &ao_msg_, &shaded_msg_ };
	dao_ros_output *outs[2] = { &ao, &shaded };
	for (int i = 0; i < 2; i++) {
		msgs[i]->header = img->header;
		msgs[i]->width = outs[i]->width;
		msgs[i]->height = outs[i]->height;
		msgs[i]->encoding = outs[i]->encoding;
		msgs[i]->is_bigendian = 0;
		msgs[i]->step = outs[i]->step;
		if (i == 0 || want_shaded) {
			msgs[i]->data.resize(outs[i]->size);
			outs[i]->data = msgs[i]->data.data();
		}
	}
	if (poses_used_)
		set_pose(img->header);
	if (dao_ros_proc_run(proc_, &depth, dao_ros_stamp_ns(img->header.stamp.sec, img->header.stamp.nsec),
			     &ao, &shaded, &err)) {
		log_error(sub_.getTopic().c_str(), err);
		return;
	}
	ao_pub_.publish(ao_msg_);
	if (want_shaded)
		shaded_pub_.publish(shaded_msg_);
	publish_depth(img, info);
	double q[4], t[3];
	if (pose_pub_.getNumSubscribers() > 0 && dao_ros_proc_pose(proc_, q, t)) {
		if (tf2_frame(img->header.frame_id) == odom_frame_)
			ROS_WARN_ONCE("~odom_frame '%s' is the depth image's own frame: camera_pose "
				      "would put the camera in itself; give ~odom_frame another name",
				      odom_frame_.c_str());
		pose_msg_.header.stamp = img->header.stamp;
		pose_msg_.header.frame_id = odom_frame_;
		pose_msg_.pose.position.x = t[0];
		pose_msg_.pose.position.y = t[1];
		pose_msg_.pose.position.z = t[2];
		pose_msg_.pose.orientation.x = q[0];
		pose_msg_.pose.orientation.y = q[1];
		pose_msg_.pose.orientation.z = q[2];
		pose_msg_.pose.orientation.w = q[3];
		pose_pub_.publish(pose_msg_);
	}
}

// The filtered depth of the frame just run, on the topics that have subscribers.
void DepthaoNode::publish_depth(const sensor_msgs::ImageConstPtr &img,
				const sensor_msgs::CameraInfoConstPtr &info)
{
	const bool want_image = depth_pub_.getNumSubscribers() > 0;
	const bool want_compressed = cdepth_pub_.getNumSubscribers() > 0;
	if (depth_info_pub_.getNumSubscribers() > 0) {
		depth_info_msg_ = *info;
		depth_info_msg_.header = img->header; // the image's stamp: they pair exactly
		depth_info_pub_.publish(depth_info_msg_);
	}
	if (!want_image && !want_compressed)
		return;
	dao_ros_output d;
	dao_error err{};
	dao_ros_proc_depth_layout(proc_, &d);
	depth_msg_.header = img->header;
	depth_msg_.width = d.width;
	depth_msg_.height = d.height;
	depth_msg_.encoding = d.encoding;
	depth_msg_.is_bigendian = 0;
	depth_msg_.step = d.step;
	depth_msg_.data.resize(d.size);
	d.data = depth_msg_.data.data();
	if (dao_ros_proc_depth(proc_, &d, &err)) {
		log_error(depth_pub_.getTopic().c_str(), err);
		return;
	}
	if (want_image)
		depth_pub_.publish(depth_msg_);
	if (!want_compressed)
		return;
	if (dao_ros_cdepth_encode(&cdepth_, &d, &err)) {
		log_error(cdepth_pub_.getTopic().c_str(), err);
		return;
	}
	cdepth_msg_.header = img->header;
	cdepth_msg_.format = cdepth_.format;
	cdepth_msg_.data.assign(cdepth_.buf, cdepth_.buf + cdepth_.len);
	cdepth_pub_.publish(cdepth_msg_);
}

} // namespace

int main(int argc, char **argv)
{
	ros::init(argc, argv, "depthao");
	DepthaoNode node;
	if (!node.start())
		return 1;
	ros::spin();
	return 0;
}
