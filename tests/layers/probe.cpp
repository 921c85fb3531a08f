// A deliberate include, compiled inside one layer's target by
// tests/layers/check_layers.sh: PX_PROBE_HEADER is a header of a higher layer
// (this must fail to build) or of the layer itself or one below (the control,
// which must build).
#include PX_PROBE_HEADER

int px_layer_probe() { return 0; }
