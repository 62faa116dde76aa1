/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <string.h>

#include <depthao/error.h>
#include "synth/sensor.h"
#include "synth/suite.h"

static const char *const names[SYNTH_SENSOR_COUNT] = {
	"clean", "gaussian", "structured-light", "active-stereo", "tof",
};

const char *synth_sensor_name(enum synth_sensor s)
{
	return (unsigned)s < SYNTH_SENSOR_COUNT ? names[s] : "unknown";
}

int synth_sensor_parse(const char *name, enum synth_sensor *out, struct dao_error *err)
{
	static const struct {
		const char *alias;
		enum synth_sensor s;
	} aliases[] = {
		{ "noisy", SYNTH_SENSOR_GAUSSIAN },
		{ "sl", SYNTH_SENSOR_STRUCTURED_LIGHT },
		{ "stereo", SYNTH_SENSOR_ACTIVE_STEREO },
	};
	for (int k = 0; k < SYNTH_SENSOR_COUNT; k++)
		if (name && strcmp(name, names[k]) == 0) {
			*out = (enum synth_sensor)k;
			return 0;
		}
	for (size_t k = 0; k < sizeof aliases / sizeof aliases[0]; k++)
		if (name && strcmp(name, aliases[k].alias) == 0) {
			*out = aliases[k].s;
			return 0;
		}
	return dao_error_set(err, -EINVAL,
			     "unknown sensor '%s': use clean, gaussian, structured-light, "
			     "active-stereo or tof", name ? name : "");
}

int synth_sensor_simulate(enum synth_sensor sensor, const struct synth_scene *scene,
			  const struct dao_camera *cam, const struct synth_image *img,
			  uint64_t seed, int threads, float *out, struct dao_error *err)
{
	return synth_sensor_simulate_frame(sensor, scene, cam, img, seed, seed, threads, out, err);
}

int synth_sensor_simulate_frame(enum synth_sensor sensor, const struct synth_scene *scene,
				const struct dao_camera *cam, const struct synth_image *img,
				uint64_t device_seed, uint64_t seed, int threads, float *out,
				struct dao_error *err)
{
	const size_t np = (size_t)cam->width * cam->height;
	switch (sensor) {
	case SYNTH_SENSOR_CLEAN:
		memcpy(out, img->depth, np * sizeof(float));
		return 0;
	case SYNTH_SENSOR_GAUSSIAN:
		memcpy(out, img->depth, np * sizeof(float));
		synth_sensor_noise(out, (int)cam->width, (int)cam->height, SYNTH_NOISE_K,
				   SYNTH_NOISE_QUANTUM, SYNTH_NOISE_DROP, seed);
		return 0;
	case SYNTH_SENSOR_STRUCTURED_LIGHT:
		return synth_sensor_structured_light(scene, cam, img, device_seed, seed, threads,
						      out, err);
	case SYNTH_SENSOR_ACTIVE_STEREO:
		return synth_sensor_active_stereo(scene, cam, img, seed, threads, out, err);
	case SYNTH_SENSOR_TOF:
		return synth_sensor_tof(scene, cam, img, seed, threads, out, err);
	case SYNTH_SENSOR_COUNT:
		break;
	}
	return dao_error_set(err, -EINVAL, "unknown sensor model %d", (int)sensor);
}
