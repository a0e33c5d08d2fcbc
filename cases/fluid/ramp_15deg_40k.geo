// Compression ramp at 15 degrees (see ramp.geo), refined to about 40 000 nodes
// (41 404 nodes, two node planes): the time-to-solution case of docs/fluid.md.
theta_deg = 15;
h = 0.008;
Include "ramp.geo";
