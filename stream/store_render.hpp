// The volume rendering of a point store (.mlc, formats/point_store.hpp) within a memory budget
// (dissertation section 7.4: volume rendering of scattered data through a meshless field; section
// 5.5: the MPU field): `meshless render pts.mlc --memory M`. The picture is ray cast in parts along z
// (kernels/ray_caster.hpp RayCastParts): the render box's z extent is cut into bands (as many as the
// store's binning grid has cell layers), the rays whose z rises are advanced through the bands from
// the bottom up, those whose z falls from the top down, and each run of bands is one slab of the
// store's field (stream/store_slab_runner.hpp: its points, its MPU field built in the whole set's
// frame, exact over the slab's box). Each ray goes on from where it stood, so the picture has the
// bytes of the same points rendered in memory (stream/field_render.hpp), for any budget and thread
// count. The frame, value range, natural spacing and empty-space boxes are the whole set's, from the
// store's plan and one pass over its bricks.
// Units: world. Memory: the budget holds a slab's points and field, 64 bytes a pixel of ray state and
// 16 bytes an empty-space box besides. Throws InvalidArgument when the field is not mpu or the budget
// cannot hold one band's slab; FormatError (no points), and what the store and the ray caster throw.
#pragma once
#include <functional>
#include <string>

#include "kernels/camera.hpp"
#include "kernels/transfer_function.hpp"
#include "stream/field_render.hpp"
#include "stream/store_field_queries.hpp"
#include "stream/store_slab_runner.hpp"

namespace meshless {

/// What a store's picture is cast over: its bounding box, value range and mean point spacing (the
/// default step), and the empty-space boxes of its points (as points_render_input's), with no field.
RenderInput store_render_input(const StoreQueries& q, const std::string& name);

/// render_field of the store's mpu field (p.field; no support test), slab by slab within
/// p.memory_bytes; progress gets the finished fraction; report (optional) the slabs' figures.
RenderResult render_store_field(const StoreQueries& q, const StoreQueryParams& p, RenderInput& in, const Camera& cam,
                                const TransferFunction& tf, const RenderOptions& o, const std::function<void(double)>& progress = {},
                                StoreQueryReport* report = nullptr);

}  // namespace meshless
