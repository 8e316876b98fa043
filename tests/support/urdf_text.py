"""URDF text for small test robots: <link> and <joint> elements with defaults, and a robot file of them."""

LINK = """<link name="{name}"><inertial><origin xyz="{com}" rpy="{rpy}"/><mass value="{mass}"/>
<inertia ixx="{ixx}" ixy="0" ixz="0" iyy="{iyy}" iyz="0" izz="{izz}"/></inertial></link>"""
JOINT = """<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>
<origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>{extra}</joint>"""


def link(name, mass=1.0, com="0 0 0.1", rpy="0 0 0", ixx=0.01, iyy=0.01, izz=0.01):
    return LINK.format(name=name, mass=mass, com=com, rpy=rpy, ixx=ixx, iyy=iyy, izz=izz)


def joint(name, parent, child, kind="revolute", xyz="0 0 0.5", rpy="0 0 0", axis="0 1 0", extra=""):
    return JOINT.format(name=name, kind=kind, parent=parent, child=child, xyz=xyz, rpy=rpy, axis=axis, extra=extra)


def write(tmp_path, *elements, name="robot.urdf"):
    """The file tmp_path / name holding a robot made of `elements`."""
    path = tmp_path / name
    path.write_text('<?xml version="1.0"?>\n<robot name="r">\n' + "\n".join(elements) + "\n</robot>\n")
    return path
