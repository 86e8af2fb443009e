"""Objects from files, refused inside what the robot saw as solid or on its path, drawn by a seed."""

import math
from dataclasses import replace

import numpy as np
import pytest

from novelty.tasks.objects.casting import cast_all, passes, sightings
from novelty.tasks.objects.placement import check_objects, draw_objects, read_objects, refusals
from novelty.tasks.objects.shapes import Box, Cylinder, Wall


def test_objects_are_read_from_csv_and_toml(tmp_path):
    csv = tmp_path / "objects.csv"
    csv.write_text("kind,name,x,y,length,width,yaw,radius,x1,y1,x2,y2,start,end\n"
                   "box,crate,5,0.6,0.4,0.3,0.5,,,,,,100,200\n"
                   "cylinder,bin,2,-0.5,,,,0.2,,,,,,\n"
                   "\n"
                   "wall,panel,,,,,,,1,2,3,2,50,\n")
    crate, bin_, panel = read_objects(csv)
    assert crate == Box("crate", 5.0, 0.6, 0.4, 0.3, 0.5, 100.0, 200.0)
    assert bin_ == Cylinder("bin", 2.0, -0.5, 0.2)
    assert panel == Wall("panel", 1.0, 2.0, 3.0, 2.0, start=50.0)
    toml = tmp_path / "objects.toml"
    toml.write_text('[[objects]]\nkind = "box"\nname = "crate"\nx = 5\ny = 0.6\nlength = 0.4\nwidth = 0.3\n'
                    'yaw = 0.5\nstart = 100\nend = 200\n\n[[objects]]\nkind = "cylinder"\nname = "bin"\n'
                    'x = 2\ny = -0.5\nradius = 0.2\n')
    assert read_objects(toml) == [crate, bin_]


@pytest.mark.parametrize("text, match", [
    ("kind,name,x,y,radius\nsphere,ball,1,1,1\n", r"line 2: kind must be one of box, cylinder, wall"),
    ("kind,name,x,y,radius,length\ncylinder,c,1,1,1,2\n", r"line 2: a cylinder has no field length"),
    ("kind,name,x,y\ncylinder,c,1,1\n", r"line 2: a cylinder needs radius"),
    ("kind,name,x,y,radius\ncylinder,c,1,one,1\n", r"line 2: y is 'one', not a number"),
    ("kind,name,x,y,radius\ncylinder,c,1,1,-1\n", r"line 2: Cylinder 'c': radius must be a positive"),
    ("kind,name,x,y,radius\ncylinder,c,1,1,1\ncylinder,c,2,2,1\n", r"c named twice"),
    ("name,x,y\nc,1,1\n", r"the header must name kind, name"),
    ("kind,name,x,y,radius\n", r"no objects"),
])
def test_bad_object_files_are_refused_with_where(tmp_path, text, match):
    path = tmp_path / "objects.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=match):
        read_objects(path)


def test_a_file_of_another_kind_is_refused(tmp_path):
    path = tmp_path / "objects.json"
    path.write_text("{}")
    with pytest.raises(ValueError, match=r"\.csv or \.toml"):
        read_objects(path)


def test_an_object_inside_a_wall_the_robot_saw_is_refused(drive):
    # the left wall's face is at y = 1: a box over y 0.85-1.35 holds the ends of the beams that hit it
    why = refusals([Box("in the wall", 5.0, 1.1, 0.5, 0.5)], drive)
    assert len(why) == 1 and "inside something the robot saw as solid" in why[0]
    with pytest.raises(ValueError, match="in the wall"):
        check_objects([Box("in the wall", 5.0, 1.1, 0.5, 0.5)], drive)


def test_an_object_on_the_robots_path_is_refused_only_while_it_stands_there(drive):
    # the drive runs along y = 0; a cylinder of radius 0.2 at y = 0.4 is 0.2 m from it, within 0.3
    why = refusals([Cylinder("in the way", 5.0, 0.4, 0.2)], drive)
    assert len(why) == 1 and "on the robot's path" in why[0] and "t=9.00 s" in why[0]
    # after the drive is over it stands in nobody's way
    assert refusals([Cylinder("later", 5.0, 0.4, 0.2, start=100.0)], drive) == []
    # beside the path, clear of the walls
    assert refusals([Cylinder("beside", 5.0, 0.6, 0.2)], drive) == []


def test_a_passer_by_is_not_a_wall(drive):
    # one scan saw something where the object will stand (a person): 1 of many scans that looked there
    person = list(drive)
    seen = replace(person[3], ranges=person[3].ranges.copy())
    seen.ranges[18] = 3.5                 # the beam ahead, from x = 1.5: ends at x = 5.0
    person[3] = seen
    assert refusals([Cylinder("bin", 5.0, 0.0, 0.2, start=100.0)], person) == []


def test_drawn_objects_stand_beside_the_path_and_are_passed_as_asked(drive):
    times = np.array([s.time for s in drive])
    poses = np.array([s.pose for s in drive])
    objects = draw_objects(drive, 2, seed=3, start=42.0, min_passes=2, before=1, within=4.0)
    assert len(objects) == 2 and all(o.start == 42.0 for o in objects)
    assert all(0.3 <= (o.radius * 2 if isinstance(o, Cylinder) else max(o.length, o.width)) <= 1.0 for o in objects)
    assert refusals(objects, drive) == []
    seen = sightings(cast_all(drive, objects, within=4.0).shortened)
    for k, obj in enumerate(objects):
        assert not seen[times < 42.0, k].any()
        assert len(set(passes(seen[:, k], poses, obj, 4.0).tolist()) - {-1}) >= 2
    assert draw_objects(drive, 2, seed=3, start=42.0, min_passes=2, within=4.0) == objects   # the seed says which


def test_too_many_passes_are_refused_with_the_best_found(drive):
    with pytest.raises(ValueError, match=r"Found 0 of 1 places .* passes 5 times after; the best had 1 and 2"):
        draw_objects(drive, 1, seed=0, start=42.0, min_passes=5, max_tries=50)


def test_objects_need_distinct_names(drive):
    with pytest.raises(ValueError, match="distinct names"):
        cast_all(drive, [Cylinder("a", 5.0, 0.6, 0.2), Cylinder("a", 2.0, 0.6, 0.2)])


def test_a_scan_sees_an_object_once_enough_beams_changed():
    assert sightings([[2, 3]], min_beams=3).tolist() == [[False, True]]
    with pytest.raises(ValueError, match="min_beams must be an int >= 1"):
        sightings([[1]], min_beams=0)
    assert math.isfinite(Box("b", 0, 0, 1, 1).size)
