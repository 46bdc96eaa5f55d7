// Decodes an lcm-logger log of tumbled with tumble-lcmtypes.jar, as lcm-spy
// would: every message of the four channels must decode as its type.
//   java -cp lcm.jar:tumble-lcmtypes.jar:. DecodeTumbleLog LOG PREFIX
// Prints one line per type (count, and fields of the last message); exits 1
// when a type is missing or a message does not decode.
import java.io.IOException;
import java.util.LinkedHashMap;
import java.util.Map;

import lcm.logging.Log;

public class DecodeTumbleLog {
    public static void main(String[] args) throws IOException {
        String prefix = args[1];
        if (!new java.io.File(args[0]).exists()) {
            System.out.println("SKIP: no log " + args[0] + " (the live end-to-end test did not run)");
            System.exit(77);
        }
        Map<String, Integer> counts = new LinkedHashMap<>();
        Map<String, String> last = new LinkedHashMap<>();
        for (String type : new String[] {"ODOM", "POSE", "STATUS", "SCAN"}) counts.put(type, 0);
        Log log = new Log(args[0], "r");
        try {
            for (;;) {
                Log.Event event = log.readNext();
                if (!event.channel.startsWith(prefix)) continue;
                String type = event.channel.substring(prefix.length());
                String fields;
                switch (type) {
                    case "ODOM": {
                        tumble.odometry_t m = new tumble.odometry_t(event.data);
                        fields = "utime " + m.utime + " seq " + m.seq + " x " + m.position_m[0];
                        break;
                    }
                    case "POSE": {
                        tumble.registration_t m = new tumble.registration_t(event.data);
                        fields = "utime " + m.utime + " scan " + m.scan_index + " iterations " + m.iterations;
                        break;
                    }
                    case "STATUS": {
                        tumble.status_t m = new tumble.status_t(event.data);
                        fields = "utime " + m.utime + " state " + m.state_name;
                        break;
                    }
                    case "SCAN": {
                        tumble.scan_t m = new tumble.scan_t(event.data);
                        fields = "utime " + m.utime + " points " + m.num_points;
                        break;
                    }
                    default:
                        continue;
                }
                counts.put(type, counts.get(type) + 1);
                last.put(type, fields);
            }
        } catch (java.io.EOFException end) {
            // the end of the log
        } finally {
            log.close();
        }
        boolean complete = true;
        for (Map.Entry<String, Integer> entry : counts.entrySet()) {
            System.out.println(prefix + entry.getKey() + ": " + entry.getValue() + " decoded; last: "
                               + last.getOrDefault(entry.getKey(), "-"));
            if (entry.getValue() == 0) complete = false;
        }
        System.exit(complete ? 0 : 1);
    }
}
