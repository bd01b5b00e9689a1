// The variance shadow map test (Donnelly and Lauritzen 2006, "Variance
// shadow maps"), shared by vsm, savsm and pcss_savsm.

// Upper bound on the lit fraction P(d >= t) from the mean and variance of
// the occluder depths d (one-sided Chebyshev / Cantelli inequality):
//     p_max = sigma² / (sigma² + (t - mu)²) for t > mu, else 1.
// It is exact when the filter region holds just two depths and t is one of
// them (a planar blocker over a planar receiver parallel to the light).
float chebyshev_upper_bound(float mean, float variance, float t, float min_variance)
{
    if (t <= mean)
        return 1.0;
    float var = max(variance, min_variance);
    float dt = t - mean;
    return var / (var + dt * dt);
}

// Light-bleeding reduction (Lauritzen, GPU Gems 3 ch. 8): maps [amount, 1]
// of p_max to [0, 1], cutting the tails that bleed through where occluders
// overlap in depth, at the price of darker, narrower penumbrae. 0 = off.
float reduce_light_bleeding(float p_max, float amount)
{
    return clamp((p_max - amount) / (1.0 - amount), 0.0, 1.0);
}
