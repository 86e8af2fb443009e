"""What leaves the habituating filter for a home of its own: routing, the parts after fitting, calibrating, single scans."""
