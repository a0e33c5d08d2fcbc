// Compression ramp at 10 degrees (see ramp.geo).
theta_deg = 10;
h = 0.02;
Include "ramp.geo";
