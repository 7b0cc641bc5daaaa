build-dev/assembly.o: build-dev/checkpoint.o build-dev/contact_modes.o build-dev/dof_map.o build-dev/element_traits.o build-dev/elements.o build-dev/errors.o build-dev/kinds.o build-dev/material_law.o build-dev/mesh.o build-dev/scene.o build-dev/sparse_matrix.o
build-dev/beam_fibre.o: build-dev/kinds.o build-dev/law_nonlinear_elastic.o build-dev/law_plastic_1d.o build-dev/section.o
build-dev/checkpoint.o: build-dev/errors.o build-dev/hdf5_file.o build-dev/kinds.o build-dev/os_utils.o build-dev/text_file.o
build-dev/cholmod_binding.o: build-dev/c_interfaces.o build-dev/errors.o build-dev/kinds.o build-dev/sparse_matrix.o
build-dev/constraint_rows.o: build-dev/errors.o build-dev/kinds.o
build-dev/contact.o: build-dev/checkpoint.o build-dev/cholmod_binding.o build-dev/constraint_rows.o build-dev/contact_modes.o build-dev/contact_multipliers.o build-dev/contact_state.o build-dev/dense_solve.o build-dev/errors.o build-dev/impact_kernels.o build-dev/inverse_ops.o build-dev/kinds.o build-dev/lcp.o build-dev/sparse_matrix.o
build-dev/contact_impact.o: build-dev/contact.o
build-dev/contact_multipliers.o: build-dev/cholmod_binding.o build-dev/constraint_rows.o build-dev/contact_modes.o build-dev/dense_solve.o build-dev/errors.o build-dev/inverse_ops.o build-dev/kinds.o build-dev/lcp.o build-dev/sparse_matrix.o
build-dev/contact_state.o: build-dev/checkpoint.o build-dev/kinds.o
build-dev/dense_solve.o: build-dev/errors.o build-dev/kinds.o build-dev/lapack_pure.o
build-dev/dof_map.o: build-dev/elements.o build-dev/mesh.o build-dev/scene.o
build-dev/element_bar2.o: build-dev/errors.o build-dev/kinds.o
build-dev/element_beam2.o: build-dev/kinds.o build-dev/section.o
build-dev/element_mass.o: build-dev/kinds.o build-dev/section.o
build-dev/element_quad.o: build-dev/errors.o build-dev/kinds.o
build-dev/element_spring.o: build-dev/errors.o build-dev/kinds.o build-dev/section.o
build-dev/element_traits.o: build-dev/material_law.o
build-dev/elements.o: build-dev/element_bar2.o build-dev/element_beam2.o build-dev/element_mass.o build-dev/element_quad.o build-dev/element_spring.o build-dev/element_traits.o build-dev/errors.o build-dev/kinds.o build-dev/section.o
build-dev/energy.o: build-dev/checkpoint.o build-dev/errors.o build-dev/kinds.o
build-dev/errors.o: build-dev/kinds.o
build-dev/fields_hdf5.o: build-dev/element_traits.o build-dev/errors.o build-dev/hdf5_file.o build-dev/kinds.o build-dev/mesh.o build-dev/os_utils.o build-dev/text_file.o build-dev/xdmf_writer.o
build-dev/gmsh_reader.o: build-dev/array_utils.o build-dev/element_traits.o build-dev/errors.o build-dev/kinds.o build-dev/line_reader.o build-dev/mesh.o build-dev/number_text.o build-dev/os_utils.o
build-dev/hdf5_file.o: build-dev/errors.o build-dev/kinds.o build-dev/os_utils.o build-dev/text_file.o
build-dev/history_writer.o: build-dev/errors.o build-dev/kinds.o build-dev/os_utils.o build-dev/text_file.o build-dev/text_format.o
build-dev/impact_kernels.o: build-dev/dense_solve.o build-dev/kinds.o
build-dev/internal_forces.o: build-dev/assembly.o build-dev/elements.o build-dev/kinds.o build-dev/material_law.o build-dev/scene.o build-dev/subincrement.o
build-dev/inverse_ops.o: build-dev/cholmod_binding.o build-dev/errors.o build-dev/kinds.o
build-dev/iteration_matrix.o: build-dev/assembly.o build-dev/cholmod_binding.o build-dev/errors.o build-dev/kinds.o
build-dev/lapack_pure.o: build-dev/kinds.o
build-dev/law_elastic.o: build-dev/kinds.o
build-dev/law_nonlinear_elastic.o: build-dev/kinds.o build-dev/subincrement.o
build-dev/law_plastic_1d.o: build-dev/kinds.o build-dev/subincrement.o
build-dev/law_von_mises.o: build-dev/kinds.o build-dev/subincrement.o
build-dev/lcp.o: build-dev/dense_solve.o build-dev/errors.o build-dev/kinds.o
build-dev/line_reader.o: build-dev/array_utils.o build-dev/errors.o build-dev/kinds.o build-dev/number_text.o
build-dev/material_law.o: build-dev/beam_fibre.o build-dev/errors.o build-dev/kinds.o build-dev/law_elastic.o build-dev/law_nonlinear_elastic.o build-dev/law_plastic_1d.o build-dev/law_von_mises.o build-dev/section.o
build-dev/mesh.o: build-dev/element_traits.o build-dev/kinds.o
build-dev/mesh_generators.o: build-dev/element_traits.o build-dev/errors.o build-dev/kinds.o build-dev/mesh.o
build-dev/newmark.o: build-dev/assembly.o build-dev/checkpoint.o build-dev/contact.o build-dev/contact_modes.o build-dev/dof_map.o build-dev/energy.o build-dev/errors.o build-dev/iteration_matrix.o build-dev/kinds.o build-dev/newmark_step.o build-dev/os_utils.o build-dev/run_outputs.o build-dev/scene.o build-dev/scene_fingerprint.o build-dev/step_state.o
build-dev/newmark_scheme.o: build-dev/kinds.o
build-dev/newmark_step.o: build-dev/assembly.o build-dev/contact.o build-dev/errors.o build-dev/iteration_matrix.o build-dev/kinds.o build-dev/scene.o build-dev/step_state.o
build-dev/number_text.o: build-dev/errors.o build-dev/kinds.o
build-dev/os_utils.o: build-dev/c_interfaces.o build-dev/errors.o build-dev/kinds.o
build-dev/rebond.o: build-dev/assembly.o build-dev/errors.o build-dev/hdf5_file.o build-dev/newmark.o build-dev/os_utils.o build-dev/scene.o build-dev/scene_loader.o build-dev/sweep.o
build-dev/run_outputs.o: build-dev/assembly.o build-dev/contact.o build-dev/energy.o build-dev/errors.o build-dev/fields_hdf5.o build-dev/history_writer.o build-dev/kinds.o build-dev/os_utils.o build-dev/scene.o build-dev/text_format.o
build-dev/scene.o: build-dev/contact_modes.o build-dev/element_traits.o build-dev/errors.o build-dev/kinds.o build-dev/material_law.o build-dev/mesh.o build-dev/section.o
build-dev/scene_conditions.o: build-dev/errors.o build-dev/kinds.o build-dev/scene.o build-dev/scene_helpers.o build-dev/statement.o build-dev/statement_schema.o
build-dev/scene_contacts.o: build-dev/errors.o build-dev/kinds.o build-dev/scene.o build-dev/scene_helpers.o build-dev/statement.o build-dev/statement_schema.o
build-dev/scene_fingerprint.o: build-dev/errors.o build-dev/kinds.o build-dev/mesh.o build-dev/number_text.o build-dev/statement.o
build-dev/scene_helpers.o: build-dev/element_traits.o build-dev/errors.o build-dev/kinds.o build-dev/mesh.o build-dev/scene.o build-dev/statement.o
build-dev/scene_loader.o: build-dev/errors.o build-dev/scene.o build-dev/scene_conditions.o build-dev/scene_contacts.o build-dev/scene_fingerprint.o build-dev/scene_materials.o build-dev/scene_mesh.o build-dev/scene_models.o build-dev/scene_parser.o build-dev/scene_run.o build-dev/statement.o build-dev/statement_schema.o
build-dev/scene_materials.o: build-dev/errors.o build-dev/kinds.o build-dev/material_law.o build-dev/scene.o build-dev/scene_helpers.o build-dev/section.o build-dev/statement.o build-dev/statement_schema.o
build-dev/scene_mesh.o: build-dev/element_traits.o build-dev/errors.o build-dev/gmsh_reader.o build-dev/kinds.o build-dev/mesh.o build-dev/mesh_generators.o build-dev/scene.o build-dev/scene_helpers.o build-dev/statement.o build-dev/statement_schema.o
build-dev/scene_models.o: build-dev/element_traits.o build-dev/elements.o build-dev/errors.o build-dev/kinds.o build-dev/material_law.o build-dev/scene.o build-dev/scene_helpers.o build-dev/statement.o build-dev/statement_schema.o
build-dev/scene_parser.o: build-dev/errors.o build-dev/kinds.o build-dev/number_text.o build-dev/statement.o build-dev/statement_schema.o
build-dev/scene_run.o: build-dev/contact_modes.o build-dev/errors.o build-dev/kinds.o build-dev/mesh.o build-dev/scene.o build-dev/scene_helpers.o build-dev/statement.o build-dev/statement_schema.o
build-dev/section.o: build-dev/kinds.o
build-dev/sparse_matrix.o: build-dev/errors.o build-dev/kinds.o
build-dev/statement.o: build-dev/errors.o build-dev/kinds.o build-dev/number_text.o
build-dev/statement_schema.o: build-dev/errors.o build-dev/statement.o
build-dev/step_state.o: build-dev/assembly.o build-dev/checkpoint.o build-dev/internal_forces.o build-dev/kinds.o build-dev/newmark_scheme.o build-dev/scene.o
build-dev/subincrement.o: build-dev/kinds.o
build-dev/sweep.o: build-dev/assembly.o build-dev/c_interfaces.o build-dev/contact.o build-dev/errors.o build-dev/kinds.o build-dev/newmark.o build-dev/os_utils.o build-dev/scene.o build-dev/scene_loader.o build-dev/sweep_metrics.o build-dev/sweep_output.o build-dev/sweep_spec.o
build-dev/sweep_metrics.o: build-dev/errors.o build-dev/kinds.o build-dev/number_text.o build-dev/os_utils.o build-dev/scene_parser.o build-dev/sweep_spec.o
build-dev/sweep_output.o: build-dev/errors.o build-dev/hdf5_file.o build-dev/kinds.o build-dev/number_text.o build-dev/sweep_metrics.o build-dev/sweep_spec.o build-dev/text_file.o
build-dev/sweep_spec.o: build-dev/errors.o build-dev/kinds.o build-dev/number_text.o build-dev/os_utils.o build-dev/scene_parser.o build-dev/statement.o build-dev/statement_schema.o
build-dev/testing.o: build-dev/kinds.o
build-dev/text_file.o: build-dev/c_interfaces.o build-dev/errors.o
build-dev/text_format.o: build-dev/c_interfaces.o build-dev/kinds.o
build-dev/xdmf_writer.o: build-dev/errors.o build-dev/kinds.o build-dev/os_utils.o build-dev/text_file.o
