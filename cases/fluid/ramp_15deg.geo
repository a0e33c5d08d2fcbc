// Compression ramp at 15 degrees (see ramp.geo).
theta_deg = 15;
h = 0.02;
Include "ramp.geo";
