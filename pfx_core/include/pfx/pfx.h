// pfx: the whole public API of the core (pfx_core) in one include, as the seed's
// physics_effects.h is: the base level (one thing at a time: shapes, pairs, joints, rays,
// math), the low level (one function per pipeline stage over caller-owned arrays, seed
// chapters 4 to 6), the high level (PfxWorld, the debug render) and the seed's names for
// what pfx names otherwise (pfx_seed_names.h).
//
// The loaders (URDF, meshes, OctoMap: pfx/loaders/) are a library of their own,
// pfx_loaders, built only where their dependencies are found; include their headers
// directly and link pfx::pfx_loaders.
#pragma once

// Base level.
#include "pfx/base_level/base/pfx_common.h"
#include "pfx/base_level/base/pfx_sort_data.h"
#include "pfx/base_level/base/pfx_utility_allocator.h"
#include "pfx/base_level/base/pfx_vec_math.h"
#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/broadphase/pfx_broadphase_proxy.h"
#include "pfx/base_level/collision/pfx_box.h"
#include "pfx/base_level/collision/pfx_capsule.h"
#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/collision/pfx_contact_shapes.h"
#include "pfx/base_level/collision/pfx_convex_mesh.h"
#include "pfx/base_level/collision/pfx_cylinder.h"
#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx/base_level/collision/pfx_mass_properties.h"
#include "pfx/base_level/collision/pfx_shape.h"
#include "pfx/base_level/collision/pfx_sphere.h"
#include "pfx/base_level/joint/pfx_joint.h"
#include "pfx/base_level/joint/pfx_joint_constraint.h"
#include "pfx/base_level/joint/pfx_joint_coupling.h"
#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/base_level/particle/pfx_particle.h"
#include "pfx/base_level/raycast/pfx_ray.h"
#include "pfx/base_level/raycast/pfx_ray_shapes.h"
#include "pfx/base_level/rigidbody/pfx_motion_type.h"
#include "pfx/base_level/rigidbody/pfx_rigid_body.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/solver/pfx_constraint_row.h"
#include "pfx/base_level/solver/pfx_solver_body.h"
#include "pfx/base_level/task/pfx_task_manager.h"
#include "pfx/base_level/task/pfx_tbb_task_manager.h"

// Low level: one header per stage, named after it (seed chapters 4 to 6), and the error
// detail every stage writes when it rejects a call.
#include "pfx/low_level/broadphase/pfx_decompose_pairs.h"
#include "pfx/low_level/broadphase/pfx_find_pairs.h"
#include "pfx/low_level/broadphase/pfx_update_broadphase_proxies.h"
#include "pfx/low_level/collision/pfx_detect_collision.h"
#include "pfx/low_level/collision/pfx_query_contacts.h"
#include "pfx/low_level/collision/pfx_refresh_contacts.h"
#include "pfx/low_level/particle/pfx_detect_particle_contacts.h"
#include "pfx/low_level/particle/pfx_integrate_particles.h"
#include "pfx/low_level/particle/pfx_query_particles.h"
#include "pfx/low_level/particle/pfx_refresh_particle_contacts.h"
#include "pfx/low_level/particle/pfx_solve_particle_constraints.h"
#include "pfx/low_level/particle/pfx_update_particles.h"
#include "pfx/low_level/pfx_error_detail.h"
#include "pfx/low_level/raycast/pfx_build_ray_bvh.h"
#include "pfx/low_level/raycast/pfx_cast_rays.h"
#include "pfx/low_level/rigidbody/pfx_apply_external_force.h"
#include "pfx/low_level/rigidbody/pfx_apply_joint_efforts.h"
#include "pfx/low_level/rigidbody/pfx_update_rigid_states.h"
#include "pfx/low_level/solver/pfx_correct_joint_positions.h"
#include "pfx/low_level/solver/pfx_island_generation.h"
#include "pfx/low_level/solver/pfx_setup_contact_constraints.h"
#include "pfx/low_level/solver/pfx_setup_joint_constraints.h"
#include "pfx/low_level/solver/pfx_setup_solver_bodies.h"
#include "pfx/low_level/solver/pfx_solve_constraints.h"
#include "pfx/low_level/sort/pfx_parallel_sort.h"

// High level.
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_character_controller.h"
#include "pfx/high_level/pfx_debug_render.h"
#include "pfx/high_level/pfx_depth_camera.h"
#include "pfx/high_level/pfx_imu_reading.h"
#include "pfx/high_level/pfx_joint_trajectory.h"
#include "pfx/high_level/pfx_particle_group.h"
#include "pfx/high_level/pfx_ragdoll.h"
#include "pfx/high_level/pfx_range_sensor.h"
#include "pfx/high_level/pfx_serialize.h"
#include "pfx/high_level/pfx_world.h"
#include "pfx/high_level/pfx_world_batch.h"

// The seed's names.
#include "pfx/pfx_seed_names.h"
