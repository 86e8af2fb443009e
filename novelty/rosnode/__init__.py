"""The live ROS 1 node (``novelty node``): each scan scored as it arrives, learned, published.

A thin shell around the offline path: the node's reading of a scan is the
bag reader's (:mod:`novelty.rosnode.reading`), its scoring the detector's
own ``score_learn_one`` (:mod:`novelty.rosnode.scoring`), so that a bag
played into the node gives, scan for scan, the novelty ``novelty run``
writes for it. Only :mod:`novelty.rosnode.node` imports rospy (ROS 1, an
optional dependency under the system Python: ``docs/guide/live-robot.md``);
the rest is plain Python, tested without ROS.

- :mod:`~novelty.rosnode.settings`: the node's private parameters, checked;
- :mod:`~novelty.rosnode.setup`: the detector, alarm and reading they make;
- :mod:`~novelty.rosnode.reading`: live messages read as a bag's;
- :mod:`~novelty.rosnode.scoring`: score, learn, count, freeze, reset, save;
- :mod:`~novelty.rosnode.stats`: the counts the diagnostics report;
- :mod:`~novelty.rosnode.node`: the rospy shell.
"""
