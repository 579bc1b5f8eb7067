"""The stages of partial-pose IK (:class:`kin.ik.partial_pose.PartialPoseIK`).

:mod:`.settings` holds the numbers of the search, :mod:`.task` the target's rows and errors,
:mod:`.context` the arm's frozen handles and one call's, :mod:`.candidates` the closed form's
branches, :mod:`.least_squares` the weighted Levenberg-Marquardt, :mod:`.starts` the starts it
runs from, :mod:`.progress` what a search has found so far, :mod:`.search` their
composition and :mod:`.outcome` the results.
"""
