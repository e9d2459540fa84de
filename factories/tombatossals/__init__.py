"""tombatossals"""
