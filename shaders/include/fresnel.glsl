// The Fresnel reflectance of a smooth dielectric: the path tracer's dielectric lobe (bsdf.glsl)
// and the Whitted integrator's glass (whitted.comp) use this one function.
#ifndef VKRT_FRESNEL_GLSL
#define VKRT_FRESNEL_GLSL

// Fresnel reflectance of a smooth dielectric for unpolarised light; eta = n_incident / n_transmitted.
float fresnel_dielectric(float cos_i, float eta, out float cos_t) {
    float sin2_t = eta * eta * max(0.0, 1.0 - cos_i * cos_i);
    if (sin2_t >= 1.0) { cos_t = 0.0; return 1.0; }
    cos_t = sqrt(1.0 - sin2_t);
    float rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    float rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

#endif
