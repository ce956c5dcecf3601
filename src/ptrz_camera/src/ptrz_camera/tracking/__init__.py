"""The camera network's pure core: find the ball in an image (segment), turn a pixel into a floor
position and combine cameras (localize), record which floor cells were seen (coverage), split the
floor between cameras while nothing is tracked (scan_plan)."""
