"""Write a 2D mesh in Gmsh's MSH 2.2 ASCII format (the structured-mesh tools: ring_mesh.py,
plate_hole_mesh.py, block_mesh.py). No Gmsh on the machine: the meshes are made in Python."""


def write(path, names, nodes, elements):
    """names: [(dimension, tag, name)] of the physical groups; nodes: [(x, y)], tagged 1..n in order;
    elements: [(gmsh_type, physical_tag, [node tags])] (1: LINE2, 8: LINE3, 3: QUAD4, 16: QUAD8...),
    the elementary entity numbered as the physical group."""
    with open(path, 'w') as f:
        f.write('$MeshFormat\n2.2 0 8\n$EndMeshFormat\n')
        f.write('$PhysicalNames\n%d\n' % len(names))
        for dim, tag, name in names:
            f.write('%d %d "%s"\n' % (dim, tag, name))
        f.write('$EndPhysicalNames\n$Nodes\n%d\n' % len(nodes))
        for k, (x, y) in enumerate(nodes):
            f.write('%d %.17g %.17g 0\n' % (k + 1, x, y))
        f.write('$EndNodes\n$Elements\n%d\n' % len(elements))
        for k, (etype, phys, conn) in enumerate(elements):
            f.write('%d %d 2 %d %d %s\n' % (k + 1, etype, phys, phys, ' '.join(str(v) for v in conn)))
        f.write('$EndElements\n')
