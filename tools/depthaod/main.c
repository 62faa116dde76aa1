/* SPDX-License-Identifier: MIT */
/*
 * depthaod: the live AO daemon.  Source plugin -> AO pipeline -> sinks,
 * configured by an INI file and the command line, controlled by signals
 * (TERM/INT stop, HUP reloads [ao]) and an optional control socket.
 */
#define _GNU_SOURCE /* sigtimedwait */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include "common/tool_clock.h"
#include "common/cli_plugins.h"
#include "config.h"
#include "control.h"
#include "daemon.h"
#include "log.h"
#include "notify.h"

#define MAX_OVERRIDES 128

struct override {
	char section[80], key[64], value[512];
};

struct options {
	const char *config, *check;
	struct override ov[MAX_OVERRIDES];
	int nov, nsinks_cli;
};

static void usage(FILE *out)
{
	fprintf(out,
		"usage: depthaod [-c FILE] [options]\n"
		"       depthaod --check-config FILE\n"
		"\n"
		"Reads depth from a source, computes ambient occlusion and publishes it to sinks\n"
		"until stopped (SIGTERM/SIGINT) or the recording ends.  SIGHUP reloads [ao].\n"
		"\n"
		"  -c, --config FILE       INI file: [source], [ao], [sink.NAME]..., [daemon]\n"
		"  --check-config FILE     validate FILE (and the options) and exit: 0 ok, 2 errors\n"
		"  --source URI            [source] uri: FILE.oni, FILE.bag, images:DIR, openni2:any, ...\n"
		"  --playback MODE         [source] playback: realtime (default) or manual\n"
		"  --loop                  [source] loop = true\n"
		"  --sink [NAME=]URI       a sink: images:DIR, y4m:- (stdout), y4m:FIFO, oni:FILE.oni\n"
		"  --stream NAME=STREAM    what sink NAME gets: shaded (default), ao, ao8, depth, overlay,\n"
		"                          filtered-depth\n"
		"  --set SECTION.KEY=VALUE any config key, e.g. --set sink.rec.queue=16\n"
		"  --PARAM VALUE           any AO parameter, e.g. --radius 0.3 (see depthao process --help)\n"
		"  --socket PATH           control socket for 'depthao ctl' (its user, root and\n"
		"                          [daemon] socket_group may connect)\n"
		"  --stats-interval S      log statistics every S seconds (0 = never; default 10)\n"
		"  --stats-json FILE       append one JSON line of statistics per interval\n"
		"  --log-level LEVEL       error, warn, info (default) or debug\n"
		"  --max-frames N          stop after N processed frames\n"
		"  --help, --version\n");
}

static int usage_fail(const char *fmt, const char *a)
{
	fputs("depthaod: ", stderr);
	fprintf(stderr, fmt, a);
	fputs(" (see 'depthaod --help')\n", stderr);
	return 2;
}

static int add_override(struct options *o, const char *section, const char *key, const char *value)
{
	if (o->nov == MAX_OVERRIDES || strlen(section) >= sizeof o->ov[0].section ||
	    strlen(key) >= sizeof o->ov[0].key || strlen(value) >= sizeof o->ov[0].value)
		return usage_fail("option '%s' is too long, or too many options", key);
	struct override *v = &o->ov[o->nov++];
	strcpy(v->section, section);
	strcpy(v->key, key);
	strcpy(v->value, value);
	return 0;
}

/* "NAME=URI" if what precedes '=' is a plain name (URIs may contain '=' later on). */
static int split_named(const char *arg, char *name, size_t cap, const char **rest)
{
	const char *eq = strchr(arg, '=');
	if (!eq || (size_t)(eq - arg) >= cap || eq == arg)
		return 0;
	for (const char *p = arg; p < eq; p++)
		if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') ||
		      *p == '-' || *p == '_'))
			return 0;
	memcpy(name, arg, (size_t)(eq - arg));
	name[eq - arg] = '\0';
	*rest = eq + 1;
	return 1;
}

static int parse_args(int argc, char **argv, struct options *o)
{
	memset(o, 0, sizeof(*o));
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		const char *v = i + 1 < argc ? argv[i + 1] : NULL;
		char name[64], section[80];
		const char *rest;
		if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
			usage(stdout);
			exit(0);
		}
		if (!strcmp(a, "--version")) {
			printf("depthaod %s\n%s\n", dao_version(), notify_describe());
			exit(0);
		}
		if (!strcmp(a, "--loop")) {
			if (add_override(o, "source", "loop", "true"))
				return 2;
			continue;
		}
		if (!strncmp(a, "--", 2) && !v)
			return usage_fail("%s needs a value", a);
		int r = 0;
		if (!strcmp(a, "-c") || !strcmp(a, "--config"))
			o->config = v;
		else if (!strcmp(a, "--check-config"))
			o->check = v;
		else if (!strcmp(a, "--source"))
			r = add_override(o, "source", "uri", v);
		else if (!strcmp(a, "--playback"))
			r = add_override(o, "source", "playback", v);
		else if (!strcmp(a, "--socket"))
			r = add_override(o, "daemon", "socket", v);
		else if (!strcmp(a, "--stats-interval"))
			r = add_override(o, "daemon", "stats_interval", v);
		else if (!strcmp(a, "--stats-json"))
			r = add_override(o, "daemon", "stats_json", v);
		else if (!strcmp(a, "--log-level"))
			r = add_override(o, "daemon", "log_level", v);
		else if (!strcmp(a, "--max-frames"))
			r = add_override(o, "daemon", "max_frames", v);
		else if (!strcmp(a, "--sink")) {
			if (!split_named(v, name, sizeof name, &rest)) {
				snprintf(name, sizeof name, "cli%d", ++o->nsinks_cli);
				rest = v;
			}
			snprintf(section, sizeof section, "sink.%s", name);
			r = add_override(o, section, "uri", rest);
		} else if (!strcmp(a, "--stream")) {
			if (!split_named(v, name, sizeof name, &rest))
				return usage_fail("--stream '%s' must be NAME=STREAM", v);
			snprintf(section, sizeof section, "sink.%s", name);
			r = add_override(o, section, "stream", rest);
		} else if (!strcmp(a, "--set")) {
			const char *eq = strchr(v, '='), *dot = eq ? memchr(v, '.', (size_t)(eq - v)) : NULL;
			const char *last = dot;
			for (const char *p = dot; p && p < eq; p++) /* sink.NAME.key: the last dot */
				if (*p == '.')
					last = p;
			if (!eq || !last || (size_t)(last - v) >= sizeof section ||
			    (size_t)(eq - last - 1) >= sizeof name)
				return usage_fail("--set '%s' must be SECTION.KEY=VALUE", v);
			memcpy(section, v, (size_t)(last - v));
			section[last - v] = '\0';
			memcpy(name, last + 1, (size_t)(eq - last - 1));
			name[eq - last - 1] = '\0';
			r = add_override(o, section, name, eq + 1);
		} else if (!strncmp(a, "--", 2) && (dao_param_find(a + 2) || !strcmp(a + 2, "quality")))
			r = add_override(o, "ao", a + 2, v);
		else
			return usage_fail("unknown option '%s'", a);
		if (r)
			return r;
		i++;
	}
	return 0;
}

/* The file, then the command line over it. */
static int build_config(const struct options *o, const char *file, struct daemon_config *c,
			char *msg, size_t len)
{
	config_defaults(c);
	if (file && config_load(c, file, msg, len) < 0)
		return -1;
	for (int i = 0; i < o->nov; i++) {
		char m[480];
		if (config_set(c, o->ov[i].section, o->ov[i].key, o->ov[i].value, m, sizeof m) < 0) {
			snprintf(msg, len, "command line: %s", m);
			return -1;
		}
	}
	if (config_check(c, msg, len) < 0)
		return -1;
	if (c->camera_warning[0])
		log_warn("%s", c->camera_warning);
	return 0;
}

static void log_stats(struct daemon *d, const char *json_path)
{
	struct json_object *j = daemon_stats(d, 1);
	struct json_object *v;
	double fps = json_object_object_get_ex(j, "fps", &v) ? json_object_get_double(v) : 0;
	long long in = json_object_object_get_ex(j, "frames_in", &v) ? json_object_get_int64(v) : 0;
	long long dropped = json_object_object_get_ex(j, "frames_dropped_in", &v) ? json_object_get_int64(v) : 0;
	long long done = json_object_object_get_ex(j, "frames_processed", &v) ? json_object_get_int64(v) : 0;
	double cpu = json_object_object_get_ex(j, "cpu_ms_per_frame", &v) ? json_object_get_double(v) : 0;
	log_info("stats: %lld in (%lld dropped), %lld processed, %.1f fps, %.1f ms CPU/frame", in,
		 dropped, done, fps, cpu);
	struct json_object *sinks;
	if (json_object_object_get_ex(j, "sinks", &sinks)) {
		for (size_t i = 0; i < json_object_array_length(sinks); i++) {
			struct json_object *s = json_object_array_get_idx(sinks, i), *f;
			const char *name = json_object_object_get_ex(s, "name", &f) ? json_object_get_string(f) : "?";
			long long out = json_object_object_get_ex(s, "frames_out", &f) ? json_object_get_int64(f) : 0;
			long long sd = json_object_object_get_ex(s, "frames_dropped", &f) ? json_object_get_int64(f) : 0;
			double med = json_object_object_get_ex(s, "latency_ms_median", &f) ? json_object_get_double(f) : 0;
			double p99 = json_object_object_get_ex(s, "latency_ms_p99", &f) ? json_object_get_double(f) : 0;
			const char *state = json_object_object_get_ex(s, "state", &f) ? json_object_get_string(f) : "";
			const char *code = json_object_object_get_ex(s, "stop_code", &f) ? json_object_get_string(f) : NULL;
			char st[48] = "";
			if (strcmp(state, "running") && strcmp(state, "waiting"))
				snprintf(st, sizeof st, ", %s%s%s%s", state, code ? " (" : "", code ? code : "",
					 code ? ")" : "");
			log_info("stats: sink %s: %lld out, %lld dropped%s, latency %.1f ms median, %.1f ms p99",
				 name, out, sd, st, med, p99);
		}
	}
	if (json_path && *json_path) {
		FILE *f = fopen(json_path, "a");
		if (f) {
			struct timespec ts;
			clock_gettime(CLOCK_REALTIME, &ts);
			json_object_object_add(j, "time", json_object_new_double((double)ts.tv_sec + ts.tv_nsec / 1e9));
			fprintf(f, "%s\n", json_object_to_json_string_ext(j, JSON_C_TO_STRING_PLAIN));
			fclose(f);
		} else {
			log_warn("cannot append to %s: %s", json_path, strerror(errno));
		}
	}
	json_object_put(j);
}

/*
 * Opens /dev/null on whichever of stdin, stdout and stderr is closed, before
 * anything else opens a file; returns a bit per fd that was.  Started with one
 * closed (depthaod 2>&-, or a careless supervisor), the first file the daemon
 * opened took its number: log lines were written into a recording at offset
 * 0, and y4m:- wrote its stream into the recording or the control socket.
 */
static unsigned open_closed_std_fds(void)
{
	unsigned closed = 0;
	for (int fd = 0; fd < 3; fd++) {
		if (fcntl(fd, F_GETFD) >= 0 || errno != EBADF)
			continue;
		closed |= 1u << fd;
		int n = open("/dev/null", fd == 0 ? O_RDONLY : O_WRONLY); /* the lowest free: fd */
		if (n > fd) {
			dup2(n, fd);
			close(n);
		}
	}
	return closed;
}

static void reload(const struct options *o, struct daemon *d)
{
	struct daemon_config c;
	struct dao_params p;
	char msg[600];
	if (!o->config) {
		log_info("SIGHUP: no config file to reload");
		return;
	}
	if (build_config(o, o->config, &c, msg, sizeof msg) < 0 ||
	    config_params(&c, &p, msg, sizeof msg) < 0) {
		log_error("reload failed, keeping the old settings: %s", msg);
		return;
	}
	daemon_set_params(d, &p);
	log_info("reloaded [ao] from %s (changes to [source], [sink.*] and [daemon] need a restart)",
		 o->config);
}

/* Signals are taken by the main thread only (sigtimedwait); threads inherit the mask. */
static void block_signals(sigset_t *set)
{
	sigemptyset(set);
	sigaddset(set, SIGTERM);
	sigaddset(set, SIGINT);
	sigaddset(set, SIGHUP);
	pthread_sigmask(SIG_BLOCK, set, NULL);
	signal(SIGPIPE, SIG_IGN); /* a reader going away is an error return, not a death */
}

/* `uri` names a plugin ("NAME:...") that is not loaded in that role: not installed, or
 * refused by the loader. */
static int names_absent_plugin(const struct dao_plugins *plugins, const char *uri, int sink)
{
	size_t n = dao_uri_prefix_len(uri);
	char name[64];
	if (!n || n >= sizeof name)
		return n != 0;
	memcpy(name, uri, n);
	name[n] = '\0';
	const struct dao_plugin *pl = dao_plugins_find(plugins, name);
	return !pl || !(sink ? pl->sink != NULL : pl->source != NULL);
}

/*
 * The source and sinks name plugins that are loaded: one that is not (not installed,
 * or refused by the loader: a required callback missing) is an error at start, not
 * retried for ever, since plugins are loaded once.  0, or -1 (logged, with the
 * registry's reason: an open of an absent plugin fails in the lookup, before any
 * plugin runs).
 */
static int check_named_plugins(const struct daemon_config *cfg, const struct dao_plugins *plugins)
{
	struct dao_error err = {0};
	if (names_absent_plugin(plugins, cfg->source_uri, 0)) {
		struct dao_source *src = NULL;
		if (dao_source_open(plugins, cfg->source_uri, NULL, &src, &err) == 0) {
			dao_source_close(src); /* not reached: the lookup fails */
			return 0;
		}
		log_error("source %s: %s; depthaod loads its plugins when it starts: check "
			  "[source] uri or the plugin, and start depthaod again",
			  cfg->source_uri, err.message);
		return -1;
	}
	for (unsigned i = 0; i < cfg->nsinks; i++) {
		if (!names_absent_plugin(plugins, cfg->sinks[i].uri, 1))
			continue;
		struct dao_sink *s = NULL;
		if (dao_sink_open(plugins, cfg->sinks[i].uri, &s, &err) == 0) {
			dao_sink_close(s, &err); /* not reached: the lookup fails */
			continue;
		}
		log_error("sink %s (%s): %s; depthaod loads its plugins when it starts: check "
			  "[sink.%s] uri or the plugin, and start depthaod again",
			  cfg->sinks[i].name, cfg->sinks[i].uri, err.message, cfg->sinks[i].name);
		return -1;
	}
	return 0;
}

/* depthaod --check FILE: the configuration read and checked, and the plugins it
 * names loaded as depthaod would load them; nothing started. */
static int check_config(const struct options *o)
{
	struct daemon_config cfg;
	char msg[700];
	if (build_config(o, o->check, &cfg, msg, sizeof msg) < 0) {
		fprintf(stderr, "depthaod: %s\n", msg);
		return 2;
	}
	struct dao_plugins *plugins = NULL;
	struct dao_error err = {0};
	if (cli_plugins_load(&plugins, &err) < 0) {
		fprintf(stderr, "depthaod: %s\n", err.message);
		return 1;
	}
	const int absent = check_named_plugins(&cfg, plugins) < 0;
	dao_plugins_free(plugins);
	if (absent)
		return 2;
	printf("%s: ok (source %s, %u sink%s)\n", o->check, cfg.source_uri, cfg.nsinks,
	       cfg.nsinks == 1 ? "" : "s");
	return 0;
}

/* The daemon and its control socket, started: 0, or -1 (logged). */
static int start_daemon(const struct daemon_config *cfg, struct dao_plugins *plugins,
			struct daemon **d, struct control **ctl)
{
	char msg[700];
	if (daemon_create(d, cfg, plugins, msg, sizeof msg) < 0) {
		log_error("%s", msg);
		return -1;
	}
	struct control_options co = {cfg->socket_path, cfg->socket_group, cfg->socket_idle_timeout_s};
	if (cfg->socket_path[0] && control_start(ctl, &co, *d, msg, sizeof msg) < 0) {
		log_error("%s", msg);
		return -1;
	}
	if (daemon_start(*d, msg, sizeof msg) < 0) {
		log_error("%s", msg);
		return -1;
	}
	log_info("depthaod %s: %s -> %u sink%s%s%s", dao_version(), cfg->source_uri, cfg->nsinks,
		 cfg->nsinks == 1 ? "" : "s", *ctl ? ", control socket " : "",
		 *ctl ? cfg->socket_path : "");
	return 0;
}

/*
 * Until SIGTERM, SIGINT or the end of the pipeline: SIGHUP reloads, and
 * every 100 ms the watchdog and status are told and the stats logged when due.
 */
static void serve(const struct options *o, const struct daemon_config *cfg, struct daemon *d,
		  const sigset_t *set)
{
	struct timespec tick = {0, 100 * 1000 * 1000};
	uint64_t last_stats_ns = tool_mono_ns();
	for (;;) {
		siginfo_t si;
		int sig = sigtimedwait(set, &si, &tick);
		if (sig == SIGTERM || sig == SIGINT) {
			log_info("%s: stopping", sig == SIGTERM ? "SIGTERM" : "SIGINT");
			notify_stopping(sig == SIGTERM ? "SIGTERM" : "SIGINT");
			break;
		}
		if (sig == SIGHUP) {
			notify_reloading();
			reload(o, d);
			notify_reloaded();
			continue;
		}
		if (daemon_finished(d)) {
			notify_stopping("the pipeline ended");
			break;
		}
		notify_tick(d);
		const uint64_t now_ns = tool_mono_ns();
		if (cfg->stats_interval_s &&
		    now_ns - last_stats_ns >= (uint64_t)cfg->stats_interval_s * 1000000000u) {
			log_stats(d, cfg->stats_json);
			last_stats_ns = now_ns;
		}
	}
}

/*
 * The control socket closed, the daemon stopped and its last stats logged:
 * the exit status (1 if it failed or a sink's output is unfinished).
 */
static int stop_daemon(struct daemon *d, struct control **ctl, const struct daemon_config *cfg)
{
	control_stop(*ctl);
	*ctl = NULL;
	daemon_stop(d);
	log_stats(d, cfg->stats_json);
	int status = daemon_failed(d) || daemon_sinks_unfinished(d) ? 1 : 0;
	if (daemon_stragglers(d)) {
		/* within the promised second, even if a frame or a write is stuck */
		if (daemon_sinks_unfinished(d))
			log_error("exiting with a sink's output unfinished");
		_exit(status);
	}
	return status;
}

int main(int argc, char **argv)
{
	struct options o;
	struct daemon_config cfg;
	char msg[700];
	unsigned closed_fds = open_closed_std_fds();
	int r = parse_args(argc, argv, &o);
	if (r)
		return r;
	if (o.check)
		return check_config(&o);
	if (build_config(&o, o.config, &cfg, msg, sizeof msg) < 0) {
		fprintf(stderr, "depthaod: %s\n", msg);
		return 2;
	}
	log_init((enum log_level)cfg.log_level);
	if (closed_fds & 2u)
		log_warn("stdout was closed when depthaod started; it is /dev/null now (a y4m:- "
			 "sink writes nowhere)");
	notify_init();
	sigset_t set;
	block_signals(&set);

	struct dao_plugins *plugins = NULL;
	struct daemon *d = NULL;
	struct control *ctl = NULL;
	struct dao_error err = {0};
	int status = 1;
	if (cli_plugins_load(&plugins, &err) < 0) {
		log_error("%s", err.message);
		return 1;
	}
	if (check_named_plugins(&cfg, plugins) < 0) {
		dao_plugins_free(plugins);
		return 2;
	}
	if (start_daemon(&cfg, plugins, &d, &ctl) == 0) {
		serve(&o, &cfg, d, &set);
		status = stop_daemon(d, &ctl, &cfg);
	}
	control_stop(ctl);
	daemon_destroy(d);
	dao_plugins_free(plugins);
	return status;
}
