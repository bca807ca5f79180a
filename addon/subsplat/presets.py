"""Measured media of Jensen et al. 2001 (table of sigma_s' and sigma_a, per mm, eta 1.3)."""

# name: (sigma_s_prime RGB, sigma_a RGB), per millimetre.
MEASURED_MEDIA = {
    "APPLE": ("Apple", (2.29, 2.39, 1.97), (0.0030, 0.0034, 0.046)),
    "CHICKEN1": ("Chicken1", (0.15, 0.21, 0.38), (0.015, 0.077, 0.19)),
    "CHICKEN2": ("Chicken2", (0.19, 0.25, 0.32), (0.018, 0.088, 0.20)),
    "CREAM": ("Cream", (7.38, 5.47, 3.15), (0.0002, 0.0028, 0.0163)),
    "KETCHUP": ("Ketchup", (0.18, 0.07, 0.03), (0.061, 0.97, 1.45)),
    "MARBLE": ("Marble", (2.19, 2.62, 3.00), (0.0021, 0.0041, 0.0071)),
    "POTATO": ("Potato", (0.68, 0.70, 0.55), (0.0024, 0.0090, 0.12)),
    "SKIMMILK": ("Skimmilk", (0.70, 1.22, 1.90), (0.0014, 0.0025, 0.0142)),
    "SKIN1": ("Skin1", (0.74, 0.88, 1.01), (0.032, 0.17, 0.48)),
    "SKIN2": ("Skin2", (1.09, 1.59, 1.79), (0.013, 0.070, 0.145)),
    "WHOLEMILK": ("Wholemilk", (2.55, 3.21, 3.77), (0.0011, 0.0024, 0.014)),
}
MEASURED_ETA = 1.3
